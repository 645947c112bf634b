"""The server process itself, as the other tests start it: it refuses a bad settings file
before it listens, saying why, and it shuts down cleanly on SIGINT with its clients
connected."""

import unittest

import bridge as b
import node


class NodeProcessTest(unittest.TestCase):
    def test_a_bad_settings_file_is_refused_before_listening(self):
        server = node.Server(settings="/**:\n  ros__parameters:\n    cooperation:\n"
                                      "      policies:\n        lane-change: sometimes\n")
        self.addCleanup(server.stop)
        with self.assertRaises(node.ServerError) as refused:
            server.start()
        message = str(refused.exception)
        self.assertIn("exited with status 1", message)
        self.assertIn("settings.param.yaml", message)  # the file is named,
        self.assertIn("sometimes", message)  # and the value it refuses
        self.assertFalse(server.running)

    def test_sigint_stops_the_server_cleanly(self):
        server = node.start(self)
        client = b.Connection(server.port)
        self.addCleanup(client.close)
        # A whole round trip: the server is serving, and so listens for SIGINT.
        client.call_ok(b.GET_POLICIES, {})
        client.subscribe(b.STEERING).at(0)
        server.stop()
        self.assertEqual(server.process.returncode, 0, "not a graceful shutdown")
        self.assertFalse(server.running)


if __name__ == "__main__":
    unittest.main()
