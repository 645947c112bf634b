"""After every accepted command, the first publication of each stream that the operator
receives after the response shows the new operator decision (the node publishes a changing
call before it answers, and a stream never goes back to an older state)."""

import unittest

import bridge as b
import node

ROUNDS = 40


class PublicationTest(unittest.TestCase):
    def setUp(self):
        self.server = node.start(self)
        self.operator = b.connect(self, self.server.port)

    def test_the_next_publication_shows_each_accepted_command(self):
        lane_change = b.module(self, self.server.port, "lane_change_left")
        intersection = b.module(self, self.server.port, "intersection")
        turn, stop = b.new_uuid(), b.new_uuid()
        steering = self.operator.subscribe(b.STEERING)
        velocity = self.operator.subscribe(b.VELOCITY)
        streams = ((steering, turn), (velocity, stop))

        for round_ in range(ROUNDS):
            # The modules report every cycle, as planners do: the scenes stay live, and their
            # syncs add publications of their own between the commands.
            lane_change.sync([b.status(turn, safe=round_ % 3 == 0, state=b.RUNNING)])
            intersection.sync([b.status(stop, safe=round_ % 5 == 0, start=30.0 - round_ / 2)])
            decision = b.ACTIVATE if round_ % 2 == 0 else b.DEACTIVATE
            # Where each stream stands as the response arrives, read on the thread that
            # delivers both, in the order the frames arrived.
            answer = b.set_commands(
                self.operator, b.command(turn, decision), b.command(stop, decision),
                mark=lambda: [recorder.count() for recorder, _ in streams])
            self.assertTrue(answer.values["status"]["success"], (round_, answer))
            for (recorder, scene), index in zip(streams, answer.mark):
                with self.subTest(round=round_, topic=recorder.name):
                    first = recorder.at(index)
                    cooperation = b.cooperation_of(first, scene)
                    self.assertIsNotNone(cooperation, first)
                    self.assertEqual(cooperation["cooperator"], {"decision": decision})

    def test_a_new_subscriber_gets_the_current_state_at_once(self):
        planner = b.module(self, self.server.port, "crosswalk")
        scene = b.new_uuid()
        planner.sync([b.status(scene)])
        b.set_commands(self.operator, b.command(scene, b.DEACTIVATE))
        late = b.connect(self, self.server.port)
        first = late.subscribe(b.VELOCITY).at(0)
        self.assertEqual(b.cooperation_of(first, scene)["cooperator"],
                         {"decision": b.DEACTIVATE})


if __name__ == "__main__":
    unittest.main()
