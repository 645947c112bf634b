"""A node with credentials, as roslibpy meets it: a client presents its token in an
Authorization header (roslibpy's ``headers=``); without one it does not connect; an operator
commands and a planning module reports, each refused what the other's role does."""

import os
import tempfile
import unittest

import bridge as b
import node

OPERATOR = "roslibpy-operator-0123456789abcdef"
MODULE = "roslibpy-module-0123456789abcdefgh"


class CredentialsTest(unittest.TestCase):
    def setUp(self):
        directory = tempfile.TemporaryDirectory(prefix="credentials-")
        self.addCleanup(directory.cleanup)
        path = os.path.join(directory.name, "credentials")
        # Only its owner may read it, or the node refuses it.
        with open(os.open(path, os.O_WRONLY | os.O_CREAT, 0o600), "w", encoding="utf-8") as file:
            file.write(f"operator ops {OPERATOR}\nmodule lanes {MODULE} lane_change_left\n")
        self.server = node.start(self, args=["--credentials", path])

    def test_without_a_token_roslibpy_does_not_connect(self):
        with self.assertRaises(Exception):
            b.Connection(self.server.port, timeout=3)
        self.assertIn("no credential presented", self.server.log())

    def test_each_role_is_let_in_with_its_token_and_does_what_it_may(self):
        module = b.Connection(self.server.port, token=MODULE)
        self.addCleanup(module.close)
        operator = b.Connection(self.server.port, token=OPERATOR)
        self.addCleanup(operator.close)
        uuid = b.new_uuid()
        synced = module.call_ok(b.SYNC, {"interface": "lane_change_left",
                                         "statuses": [b.status(uuid, safe=False)]})
        self.assertTrue(synced["success"], synced)
        answer = operator.call_ok(b.SET_COMMANDS, {"commands": [
            {"uuid": b.uuid_msg(uuid), "cooperator": {"decision": 2}}]})
        self.assertTrue(answer["status"]["success"], answer)
        # The module may not command; the operator may not report.
        refused = module.call(b.SET_COMMANDS, {"commands": []})
        self.assertFalse(refused.result)
        self.assertIn("is the operator's", str(refused.values))
        refused = operator.call(b.SYNC, {"interface": "lane_change_left", "statuses": []})
        self.assertFalse(refused.result)
        self.assertIn("is the planning modules'", str(refused.values))


if __name__ == "__main__":
    unittest.main()
