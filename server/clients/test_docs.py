"""docs/server.md's roslibpy example, run as written (its port changed) against a node with
one scene a planning module reports: it commands that scene and prints the success."""

import pathlib
import re
import subprocess
import sys
import unittest

import bridge as b
import node

DOCS = pathlib.Path(__file__).resolve().parents[2] / "docs" / "server.md"


class DocsExampleTest(unittest.TestCase):
    def test_the_operator_example_commands_the_live_scene(self):
        server = node.start(self)
        module = b.Connection(server.port)
        self.addCleanup(module.close)
        uuid = b.new_uuid()
        module.call_ok(b.SYNC, {"interface": "intersection", "statuses": [b.status(uuid)]})
        example = re.search(r"```python\n(import time\n.*?)```", DOCS.read_text(), re.S)
        self.assertIsNotNone(example, "the example is in docs/server.md")
        code = example.group(1).replace("port=9090", f"port={server.port}")
        code += "\nros.terminate()\n"
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                              timeout=30, check=False)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("{'success': True, 'code': 0, 'message': ''}", done.stdout)


if __name__ == "__main__":
    unittest.main()
