"""The stack test's peer (`tools/stack-test`): see `__main__.py`."""
