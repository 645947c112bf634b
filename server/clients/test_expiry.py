"""Scenes whose module stops reporting them expire after the TTL, here a short one from a
settings file of the test's own (docs/settings.md), so the suite need not wait 10 s."""

import time
import unittest

import bridge as b
import node

TTL_MS = 600
# The node ticks its core every 100 ms with the time since the last tick, so a scene synced
# just before a tick is aged by the whole tick: it can expire up to one tick early.
TICK_S = 0.1

SETTINGS = f"""\
/**:
  ros__parameters:
    cooperation:
      policies:
        avoidance:
          change: optional
          return: optional
        crosswalk: optional
        intersection: optional
        lane-change: optional
      limits:
        ttl_ms: {TTL_MS}
"""


class ExpiryTest(unittest.TestCase):
    def setUp(self):
        self.server = node.start(self, settings=SETTINGS)
        self.operator = b.connect(self, self.server.port)

    def test_the_settings_apply(self):
        self.assertEqual(set(b.get_policies(self.operator)), {
            ("avoidance", "change"), ("avoidance", "return"), ("crosswalk", ""),
            ("intersection", ""), ("lane-change", "")})

    def test_a_scene_not_synced_again_expires_after_the_ttl(self):
        planner = b.module(self, self.server.port, "intersection")
        velocity = self.operator.subscribe(b.VELOCITY)
        scene = b.new_uuid()
        sent = time.monotonic()
        planner.sync([b.status(scene, start=20.0)])
        velocity.wait(lambda m: b.factor_of(m, scene), since=0)
        velocity.wait(lambda m: b.factor_of(m, scene) is None, timeout=TTL_MS / 1000 + 2)
        gone = time.monotonic() - sent
        self.assertGreaterEqual(gone, TTL_MS / 1000 - TICK_S, "expired before the TTL")

        # Expired is retired: the module cannot report it again, nor the operator command it.
        response = planner.sync([b.status(scene, start=20.0)])
        self.assertFalse(response["success"])
        self.assertNotEqual(response["results"][0]["message"], "")
        self.assertIsNone(b.activation_of(response, scene))
        answer = b.set_commands(self.operator, b.command(scene, b.ACTIVATE))
        self.assertFalse(answer.values["status"]["success"])
        self.assertIsNone(b.factor_of(velocity.next(), scene))

    def test_a_scene_synced_every_cycle_stays(self):
        planner = b.module(self, self.server.port, "lane_change_left")
        steering = self.operator.subscribe(b.STEERING)
        kept, dropped = b.new_uuid(), b.new_uuid()
        planner.sync([b.status(kept), b.status(dropped)])
        start = steering.count()
        steering.wait(lambda m: b.factor_of(m, kept) and b.factor_of(m, dropped), since=0)
        # The module's planning cycle, 100 ms, over three TTLs; it reports only `kept`.
        began = time.monotonic()
        while time.monotonic() - began < 3 * TTL_MS / 1000:
            response = planner.sync([b.status(kept)])
            self.assertTrue(response["success"], response)
            time.sleep(0.1)
        # `dropped` went, and `kept` was in every publication all along.
        received = steering.since(start)
        self.assertTrue(any(b.factor_of(m, dropped) is None for m in received))
        self.assertTrue(all(b.factor_of(m, kept) for m in received),
                        [len(m["factors"]) for m in received])


if __name__ == "__main__":
    unittest.main()
