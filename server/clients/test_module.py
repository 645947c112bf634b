"""A planning module's side, through roslibpy: it syncs its scenes through
/cooperation/rtc/sync on a connection of its own, and an operator on another connection sees
them in the factors and decides; the module reads the decisions in its next sync."""

import unittest

import bridge as b
import node


class ModuleTest(unittest.TestCase):
    def setUp(self):
        self.server = node.start(self)
        self.operator = b.connect(self, self.server.port)

    def test_a_synced_scene_is_in_the_factors(self):
        intersection = b.module(self, self.server.port, "intersection")
        lane_change = b.module(self, self.server.port, "lane_change_left")
        velocity = self.operator.subscribe(b.VELOCITY)
        steering = self.operator.subscribe(b.STEERING)
        stop, turn = b.new_uuid(), b.new_uuid()

        response = intersection.sync([b.status(stop, safe=True, state=b.RUNNING, start=35.0,
                                               finish=35.0)])
        self.assertTrue(response["success"], response)
        self.assertEqual(response["message"], "")
        self.assertEqual([r["success"] for r in response["results"]], [True])
        [reported] = response["statuses"]["statuses"]
        self.assertEqual(reported["module"], {"type": 8})  # INTERSECTION
        self.assertEqual(reported["state"], {"type": b.RUNNING})
        self.assertTrue(reported["safe"])
        self.assertTrue(reported["auto_mode"])  # optional: the module's decision goes
        self.assertEqual(b.activation_of(response, stop), {
            "uuid": b.uuid_msg(stop), "activated": True,
            "force_activated": False, "force_deactivated": False})

        factor = b.factor_of(velocity.wait(lambda m: b.factor_of(m, stop)), stop)
        self.assertEqual(factor["behavior"], "intersection")
        self.assertEqual(factor["sequence"], "")
        self.assertEqual(factor["distance"], 35.0)
        self.assertEqual(factor["cooperation"], [{
            "uuid": b.uuid_msg(stop),
            "autonomous": {"decision": b.ACTIVATE},
            "cooperator": {"decision": b.UNDECIDED},
            "cancellable": True,
        }])

        lane_change.sync([b.status(turn, safe=False, start=10.0, finish=50.0)])
        factor = b.factor_of(steering.wait(lambda m: b.factor_of(m, turn)), turn)
        self.assertEqual(factor["behavior"], "lane-change")
        self.assertEqual(factor["direction"], b.LEFT)
        self.assertEqual(factor["distance"], [10.0, 50.0])
        self.assertEqual(factor["cooperation"][0]["autonomous"], {"decision": b.DEACTIVATE})

        # A later report moves the scene and changes the module's decision.
        lane_change.sync([b.status(turn, safe=True, state=b.RUNNING, start=4.0, finish=44.0)])
        factor = b.factor_of(steering.wait(
            lambda m: (b.factor_of(m, turn) or {}).get("distance") == [4.0, 44.0]), turn)
        self.assertEqual(factor["cooperation"][0]["autonomous"], {"decision": b.ACTIVATE})

    def test_the_operators_command_reaches_the_module(self):
        planner = b.module(self, self.server.port, "lane_change_left")
        scene = b.new_uuid()
        response = planner.sync([b.status(scene, safe=False, state=b.RUNNING)])
        self.assertFalse(b.activation_of(response, scene)["activated"])
        # (module says safe, operator decides) -> (activated, force activated, force
        # deactivated, command_status, auto_mode). A force flag is the operator overruling
        # the module; force-deactivated needs a running scene.
        steps = [
            ((False, b.ACTIVATE), (True, True, False, b.RTC_ACTIVATE, False)),
            ((True, b.DEACTIVATE), (False, False, True, b.RTC_DEACTIVATE, False)),
            ((True, b.ACTIVATE), (True, False, False, b.RTC_ACTIVATE, False)),
            ((False, b.DEACTIVATE), (False, False, False, b.RTC_DEACTIVATE, False)),
            ((True, b.AUTONOMOUS), (True, False, False, b.RTC_DEACTIVATE, True)),
            ((False, b.AUTONOMOUS), (False, False, False, b.RTC_DEACTIVATE, True)),
            ((True, b.UNDECIDED), (True, False, False, b.RTC_DEACTIVATE, True)),
        ]
        for (safe, decision), expected in steps:
            with self.subTest(safe=safe, decision=decision):
                planner.sync([b.status(scene, safe=safe, state=b.RUNNING)])
                answer = b.set_commands(self.operator, b.command(scene, decision))
                self.assertTrue(answer.values["status"]["success"], answer)
                response = planner.sync([b.status(scene, safe=safe, state=b.RUNNING)])
                activated, forced_on, forced_off, command_status, auto = expected
                self.assertEqual(b.activation_of(response, scene), {
                    "uuid": b.uuid_msg(scene), "activated": activated,
                    "force_activated": forced_on, "force_deactivated": forced_off})
                reported = b.status_of(response, scene)
                self.assertEqual(reported["command_status"], {"type": command_status})
                self.assertEqual(reported["auto_mode"], auto)
                self.assertEqual(reported["safe"], safe)

    def test_a_required_policy_holds_the_scene_for_the_operator(self):
        self.operator.call_ok(
            b.SET_POLICIES, {"policies": [b.policy("lane-change", b.REQUIRED)]})
        planner = b.module(self, self.server.port, "lane_change_right")
        scene = b.new_uuid()
        response = planner.sync([b.status(scene, safe=True)])
        self.assertFalse(b.activation_of(response, scene)["activated"])
        self.assertFalse(b.status_of(response, scene)["auto_mode"])
        b.set_commands(self.operator, b.command(scene, b.ACTIVATE))
        response = planner.sync([b.status(scene, safe=True)])
        self.assertTrue(b.activation_of(response, scene)["activated"])

    def test_a_removed_scene_leaves_the_factors(self):
        planner = b.module(self, self.server.port, "crosswalk")
        kept, removed = b.new_uuid(), b.new_uuid()
        planner.sync([b.status(kept, start=20.0), b.status(removed, start=8.0)])
        velocity = self.operator.subscribe(b.VELOCITY)
        velocity.wait(lambda m: b.factor_of(m, kept) and b.factor_of(m, removed), since=0)

        response = planner.sync([b.status(kept, start=19.0)], removed=[removed])
        self.assertTrue(response["success"], response)
        self.assertEqual([r["success"] for r in response["results"]], [True, True])
        self.assertIsNone(b.activation_of(response, removed))
        self.assertIsNotNone(b.activation_of(response, kept))
        gone = velocity.wait(lambda m: b.factor_of(m, removed) is None)
        self.assertIsNotNone(b.factor_of(gone, kept))

        # The identifier is retired: neither removed nor reported again.
        response = planner.sync(removed=[removed])
        self.assertFalse(response["success"])
        self.assertFalse(response["results"][0]["success"])
        self.assertNotEqual(response["results"][0]["message"], "")
        response = planner.sync([b.status(removed)])
        self.assertFalse(response["results"][0]["success"])
        self.assertNotEqual(response["results"][0]["message"], "")
        self.assertIsNone(b.factor_of(velocity.next(), removed))
        # And the operator can no longer command it.
        answer = b.set_commands(self.operator, b.command(removed, b.ACTIVATE))
        self.assertFalse(answer.values["status"]["success"])

    def test_a_finished_scene_leaves_the_factors(self):
        planner = b.module(self, self.server.port, "goal_planner")
        scene = b.new_uuid()
        planner.sync([b.status(scene, state=b.RUNNING)])
        steering = self.operator.subscribe(b.STEERING)
        steering.wait(lambda m: b.factor_of(m, scene), since=0)
        response = planner.sync([b.status(scene, state=b.SUCCEEDED)])
        self.assertTrue(response["success"], response)
        self.assertIsNone(b.activation_of(response, scene))
        steering.wait(lambda m: b.factor_of(m, scene) is None)

    def test_an_avoidance_states_its_sequences(self):
        avoidance = b.module(self, self.server.port, "static_obstacle_avoidance_right")
        self.operator.call_ok(
            b.SET_POLICIES, {"policies": [b.policy("avoidance", b.REQUIRED, "return")]})
        steering = self.operator.subscribe(b.STEERING)
        out, back = b.new_uuid(), b.new_uuid()
        response = avoidance.sync(
            [b.status(out, safe=True, state=b.RUNNING, start=5.0, finish=30.0),
             b.status(back, safe=True, start=40.0, finish=70.0)],
            sequences=[(out, "change"), (back, "return")])
        self.assertTrue(response["success"], response)
        # The shift out is optional and follows the module; the return waits for the operator.
        self.assertTrue(b.activation_of(response, out)["activated"])
        self.assertFalse(b.activation_of(response, back)["activated"])
        self.assertEqual({s["module"]["type"] for s in response["statuses"]["statuses"]},
                         {4})  # AVOIDANCE_RIGHT

        seen = steering.wait(lambda m: b.factor_of(m, out) and b.factor_of(m, back))
        for scene, sequence in ((out, "change"), (back, "return")):
            factor = b.factor_of(seen, scene)
            self.assertEqual((factor["behavior"], factor["sequence"]), ("avoidance", sequence))
            self.assertEqual(factor["direction"], b.RIGHT)

        # Later reports may leave the sequence out; stating the other one is refused.
        response = avoidance.sync([b.status(out, state=b.RUNNING, start=3.0, finish=28.0)])
        self.assertTrue(response["success"], response)
        response = avoidance.sync([b.status(out, state=b.RUNNING)], sequences=[(out, "return")])
        self.assertFalse(response["results"][0]["success"])
        self.assertNotEqual(response["results"][0]["message"], "")

        # A new scene without its sequence is refused, naming what to do, and not registered.
        unstated = b.new_uuid()
        response = avoidance.sync([b.status(unstated)])
        self.assertFalse(response["success"])
        self.assertIn("state its sequence", response["results"][0]["message"])
        self.assertIsNone(b.activation_of(response, unstated))
        # A sequence the interface does not bind is refused too.
        odd = b.new_uuid()
        response = avoidance.connection.call_ok(b.SYNC, {
            "interface": avoidance.interface, "statuses": [b.status(odd)],
            "sequences": [{"uuid": b.uuid_msg(odd), "sequence": "merge-in"}]})
        self.assertFalse(response["results"][0]["success"])
        self.assertIsNone(b.factor_of(steering.next(), unstated))
        self.assertIsNone(b.factor_of(steering.next(), odd))

    def test_a_scene_belongs_to_the_interface_that_reported_it(self):
        left = b.module(self, self.server.port, "lane_change_left")
        right = b.module(self, self.server.port, "lane_change_right")
        scene = b.new_uuid()
        left.sync([b.status(scene, safe=False)])
        for response in (right.sync([b.status(scene, safe=True)]), right.sync(removed=[scene])):
            self.assertFalse(response["success"])
            self.assertIn("lane_change_left", response["results"][0]["message"])
            self.assertIsNone(b.activation_of(response, scene))
        response = left.sync()
        self.assertFalse(b.status_of(response, scene)["safe"])

    def test_factors_are_nearest_first(self):
        planner = b.module(self, self.server.port, "lane_change_left")
        other = b.module(self, self.server.port, "start_planner")
        far, near, middle = b.new_uuid(), b.new_uuid(), b.new_uuid()
        planner.sync([b.status(far, start=30.0, finish=60.0),
                      b.status(near, start=5.0, finish=20.0)])
        other.sync([b.status(middle, start=12.0, finish=25.0)])
        steering = self.operator.subscribe(b.STEERING)
        seen = steering.wait(lambda m: all(b.factor_of(m, u) for u in (far, near, middle)),
                             since=0)
        order = [f["cooperation"][0]["uuid"]["uuid"] for f in seen["factors"]]
        self.assertEqual(order, [near, middle, far])

    def test_an_unknown_interface_is_refused(self):
        planner = b.module(self, self.server.port, "dynamic_obstacle_avoidance")
        steering = self.operator.subscribe(b.STEERING)
        velocity = self.operator.subscribe(b.VELOCITY)
        scene = b.new_uuid()
        response = planner.sync([b.status(scene)])
        self.assertFalse(response["success"])
        self.assertIn("dynamic_obstacle_avoidance", response["message"])
        self.assertEqual(response["results"], [])
        self.assertEqual(response["activations"], [])
        self.assertIsNone(b.factor_of(steering.next(), scene))
        self.assertIsNone(b.factor_of(velocity.next(), scene))
        # The module's connection still works.
        planner.interface = "intersection"
        self.assertTrue(planner.sync([b.status(scene)])["success"])

    def test_malformed_syncs_are_refused_with_the_field_named(self):
        planner = b.module(self, self.server.port, "crosswalk")
        scene = b.new_uuid()
        bad_state = dict(b.status(scene), state={"type": 9})
        cases = [
            ({"interface": "crosswalk", "statuses": [bad_state]}, "state"),
            ({"interface": "crosswalk", "statuses": [dict(b.status(scene), colour=1)]},
             "statuses[0]"),
            ({"interface": "crosswalk", "statuses": [b.status(scene[:15])]}, "statuses[0]"),
            ({"interface": "crosswalk", "colour": 1}, "colour"),
            ({"statuses": []}, "interface"),
        ]
        velocity = self.operator.subscribe(b.VELOCITY)
        for args, named in cases:
            with self.subTest(args=args):
                response = planner.connection.call_ok(b.SYNC, args)
                self.assertFalse(response["success"], response)
                messages = [response["message"]] + [r["message"] for r in response["results"]]
                self.assertTrue(any(named in m for m in messages), messages)
        self.assertIsNone(b.factor_of(velocity.next(), scene))


if __name__ == "__main__":
    unittest.main()
