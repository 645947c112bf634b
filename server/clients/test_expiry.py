"""Scenes whose module stops reporting them expire after the TTL, here a short one from a
settings file of the test's own (docs/settings.md), so the suite need not wait 10 s."""

import time
import unittest

import bridge as b
import node

TTL_MS = 600



def settings(ttl_ms):
    return f"""\
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
        ttl_ms: {ttl_ms}
"""


SETTINGS = settings(TTL_MS)


class ExpiryTest(unittest.TestCase):
    def setUp(self):
        self.server = node.start(self, settings=SETTINGS)
        self.operator = b.connect(self, self.server.port)

    def test_the_settings_apply(self):
        self.assertEqual(set(b.get_policies(self.operator)), {
            ("avoidance", "change"), ("avoidance", "return"), ("crosswalk", ""),
            ("intersection", ""), ("lane-change", "")})

    def test_a_scene_not_synced_again_expires(self):
        planner = b.module(self, self.server.port, "intersection")
        velocity = self.operator.subscribe(b.VELOCITY)
        scene = b.new_uuid()
        sent = time.monotonic()
        planner.sync([b.status(scene, start=20.0)])
        velocity.wait(lambda m: b.factor_of(m, scene), since=0)
        velocity.wait(lambda m: b.factor_of(m, scene) is None, timeout=TTL_MS / 1000 + 2)
        gone = time.monotonic() - sent
        # Not at once; ExpiryBoundTest holds the node to the TTL itself.
        self.assertGreaterEqual(gone, TTL_MS / 2000, "expired long before the TTL")

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
        steering.wait(lambda m: b.factor_of(m, kept) and b.factor_of(m, dropped), since=0)
        # From here on every publication shows the state after that sync (the first one, sent
        # as the subscription started, may show the state before it).
        start = steering.count()
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


class ExpiryBoundTest(unittest.TestCase):
    """No scene expires before its owner has left it unreported for the TTL
    ([COOP-TIME-EXPIRE.1]: a scene expires when its age is greater than the TTL).

    The node brings the core's time up to now before each sync (`Engine::handle`,
    adapters/src/engine/mod.rs), so a scene synced between two of the node's ticks is not
    charged the time before it was reported; without that it expired up to an interval early.

    Each trial syncs a new scene at a different point of a 100 ms interval (the publication
    interval, at which the node also tells the core the time), then polls with empty syncs,
    which report the interface's scenes without refreshing them, until it is gone. From the
    sync's request to the answer that misses it is at least as long as the scene went
    unreported, so that time must not be under the TTL. A TTL of 250 ms is between multiples
    of the interval, so a node that charged a scene the time before its report would show
    the early expiry for scenes synced in the later half of an interval.
    """

    TTL_MS = 250

    def setUp(self):
        self.server = node.start(self, settings=settings(self.TTL_MS))

    def test_no_scene_expires_before_the_ttl(self):
        planner = b.module(self, self.server.port, "crosswalk")
        trials = []
        for offset_ms in range(0, 100, 10):
            time.sleep(offset_ms / 1000)  # the phase within the tick interval, by design
            scene = b.new_uuid()
            sent = time.monotonic()
            self.assertTrue(planner.sync([b.status(scene)])["success"])
            b.wait_for(lambda: b.activation_of(planner.sync(), scene) is None,
                       self.TTL_MS / 1000 + 2, "the scene to expire", interval=0.002)
            trials.append((offset_ms, round((time.monotonic() - sent) * 1000)))
        early = [(offset, lived) for offset, lived in trials if lived < self.TTL_MS]
        self.assertEqual(early, [], f"(offset, ms unreported) of scenes expired before the "
                                    f"{self.TTL_MS} ms TTL; all trials: {trials}")


if __name__ == "__main__":
    unittest.main()
