"""The operator's side of the AD API, through roslibpy: the policy services, set_commands and
the two factor streams, on a node with the default settings (config/cooperation.param.yaml)."""

import base64
import unittest

import bridge as b
import node

# config/cooperation.param.yaml: every standard module, each optional.
CONFIGURED = {
    ("avoidance", "change"), ("avoidance", "return"), ("crosswalk", ""), ("goal-planner", ""),
    ("intersection", ""), ("lane-change", ""), ("no-stopping-area", ""), ("rear-check", ""),
    ("roundabout", ""), ("start-planner", ""), ("traffic-signal", ""),
    ("user-defined-attention-area", ""), ("virtual-traffic-light", ""),
}


class OperatorTest(unittest.TestCase):
    def setUp(self):
        self.server = node.start(self)
        self.operator = b.connect(self, self.server.port)

    def test_get_policies_lists_the_configured_modules(self):
        values = self.operator.call_ok(b.GET_POLICIES, {})
        self.assertEqual(values["status"], {"success": True, "code": 0, "message": ""})
        listed = [(p["behavior"], p["sequence"]) for p in values["policies"]]
        self.assertEqual(len(listed), len(set(listed)), "a module listed twice")
        self.assertEqual(set(listed), CONFIGURED)
        self.assertEqual({p["policy"] for p in values["policies"]}, {b.OPTIONAL})

    def test_set_policies_changes_one_module(self):
        before = b.get_policies(self.operator)
        values = self.operator.call_ok(
            b.SET_POLICIES, {"policies": [b.policy("lane-change", b.REQUIRED)]})
        self.assertEqual(values["status"], {"success": True, "code": 0, "message": ""})
        after = b.get_policies(self.operator)
        self.assertEqual(after[("lane-change", "")], b.REQUIRED)
        self.assertEqual({k: v for k, v in after.items() if k != ("lane-change", "")},
                         {k: v for k, v in before.items() if k != ("lane-change", "")})
        # A sequence of its own: the return of an avoidance, not its change.
        self.operator.call_ok(
            b.SET_POLICIES, {"policies": [b.policy("avoidance", b.REQUIRED, "return")]})
        after = b.get_policies(self.operator)
        self.assertEqual(after[("avoidance", "return")], b.REQUIRED)
        self.assertEqual(after[("avoidance", "change")], b.OPTIONAL)

    def test_set_policies_refusals_change_nothing(self):
        before = b.get_policies(self.operator)
        refusals = [
            # Not configured: a well-formed extension name no configuration names.
            ([b.policy("lane-chnage", b.REQUIRED)], "lane-chnage"),
            # Not a behaviour at all.
            ([b.policy("lane_change", b.REQUIRED)], "policies[0].behavior"),
            # No such policy constant.
            ([b.policy("lane-change", 9)], "policies[0].policy"),
            # All or nothing: the valid first setting is not applied either.
            ([b.policy("crosswalk", b.REQUIRED), b.policy("lane-chnage", b.REQUIRED)],
             "lane-chnage"),
        ]
        for policies, named in refusals:
            with self.subTest(policies=policies):
                values = self.operator.call_ok(b.SET_POLICIES, {"policies": policies})
                self.assertFalse(values["status"]["success"], values)
                self.assertIn(named, values["status"]["message"])
                self.assertEqual(b.get_policies(self.operator), before)

    def test_set_commands_on_a_live_scene(self):
        planner = b.module(self, self.server.port, "lane_change_left")
        scene = b.new_uuid()
        planner.sync([b.status(scene, safe=False)])
        steering = self.operator.subscribe(b.STEERING)
        for decision in (b.ACTIVATE, b.DEACTIVATE, b.AUTONOMOUS, b.UNDECIDED):
            with self.subTest(decision=decision):
                answer = b.set_commands(self.operator, b.command(scene, decision))
                self.assertTrue(answer.result)
                self.assertEqual(answer.values["status"],
                                 {"success": True, "code": 0, "message": ""})
                steering.wait(lambda m: (b.cooperation_of(m, scene) or {})
                              .get("cooperator") == {"decision": decision})

    def test_identifiers_as_base64(self):
        # rosbridge writes uint8 arrays as base64 strings, and the node reads them so.
        planner = b.module(self, self.server.port, "crosswalk")
        scene = b.new_uuid()
        encoded = {"uuid": base64.b64encode(bytes(scene)).decode("ascii")}
        response = planner.sync([dict(b.status(scene), uuid=encoded)])
        self.assertTrue(response["success"], response)
        self.assertEqual(response["activations"][0]["uuid"], b.uuid_msg(scene))
        answer = b.set_commands(self.operator,
                                {"uuid": encoded, "cooperator": {"decision": b.DEACTIVATE}})
        self.assertTrue(answer.values["status"]["success"], answer)
        self.assertFalse(b.activation_of(planner.sync(), scene)["activated"])

    def test_an_empty_batch_has_no_effect(self):
        answer = b.set_commands(self.operator)
        self.assertEqual(answer.values["status"]["success"], True)
        self.assertEqual(answer.values["status"]["code"], 60001)
        self.assertIn("empty", answer.values["status"]["message"])

    def test_refused_commands_change_nothing(self):
        planner = b.module(self, self.server.port, "lane_change_left")
        scene = b.new_uuid()
        planner.sync([b.status(scene, safe=True)])
        self.assertTrue(b.set_commands(self.operator, b.command(scene, b.DEACTIVATE))
                        .values["status"]["success"])
        policies = b.get_policies(self.operator)
        steering = self.operator.subscribe(b.STEERING)
        steering.wait(lambda m: b.factor_of(m, scene) is not None, since=0)
        unknown = b.new_uuid()
        refusals = [
            ("an unknown scene", [b.command(unknown, b.ACTIVATE)], "unknown scene"),
            ("an undefined decision", [b.command(scene, 7)],
             "commands[0].cooperator.decision: 7 is not a CooperationDecision constant"),
            ("a decision as text", [b.command(scene, "2")],
             "commands[0].cooperator.decision: invalid type"),
            ("no decision", [{"uuid": b.uuid_msg(scene)}], "UNKNOWN"),
            ("a 15-byte identifier", [{"uuid": {"uuid": scene[:15]},
                                       "cooperator": {"decision": b.ACTIVATE}}],
             "a UUID has 16 bytes, not 15"),
            ("a field the message does not have",
             [dict(b.command(scene, b.ACTIVATE), extra=1)], "extra"),
            ("the scene twice", [b.command(scene, b.ACTIVATE), b.command(scene, b.ACTIVATE)],
             "twice"),
            ("a valid command beside an unknown scene",
             [b.command(scene, b.ACTIVATE), b.command(unknown, b.ACTIVATE)], "unknown scene"),
        ]
        for what, commands, named in refusals:
            with self.subTest(what):
                answer = b.set_commands(self.operator, *commands)
                self.assertTrue(answer.result, answer)
                status = answer.values["status"]
                self.assertFalse(status["success"], status)
                self.assertEqual(status["code"], b.PARAMETER_ERROR)
                self.assertIn(named, status["message"])
                self.assert_unchanged(steering, scene, policies)
        self.assertEqual(self.operator.statuses(), [], "a refused command is no protocol error")

    def test_a_wrong_type_name_is_refused(self):
        planner = b.module(self, self.server.port, "lane_change_left")
        scene = b.new_uuid()
        planner.sync([b.status(scene, safe=True)])
        policies = b.get_policies(self.operator)
        steering = self.operator.subscribe(b.STEERING)
        steering.wait(lambda m: b.factor_of(m, scene) is not None, since=0)
        wrong = "autoware_adapi_v1_msgs/srv/SetCooperationPolicies"
        answer = self.operator.call(
            b.SET_COMMANDS, {"commands": [b.command(scene, b.DEACTIVATE)]}, type_name=wrong)
        self.assertFalse(answer.result)
        self.assertIn(b.SET_COMMANDS[1], answer.values)
        self.assertIn(wrong, answer.values)
        # The status frame came before the response, and says the same.
        [status] = self.operator.statuses()
        self.assertEqual(status["level"], "error")
        self.assertEqual(status["msg"], answer.values)
        self.assertTrue(status["id"].startswith("call_service:" + b.SET_COMMANDS[0]))
        self.assert_unchanged(steering, scene, policies, cooperator=b.UNDECIDED)
        # The right type, in either form, is accepted.
        for given in (b.SET_COMMANDS[1], "autoware_adapi_v1_msgs/SetCooperationCommands"):
            with self.subTest(type=given):
                answer = self.operator.call(
                    b.SET_COMMANDS, {"commands": [b.command(scene, b.DEACTIVATE)]},
                    type_name=given)
                self.assertTrue(answer.result, answer)
                self.assertTrue(answer.values["status"]["success"], answer)

    def assert_unchanged(self, steering, scene, policies, cooperator=b.DEACTIVATE):
        self.assertEqual(b.get_policies(self.operator), policies)
        # A refused call publishes nothing; the next periodic publication shows the same.
        cooperation = b.cooperation_of(steering.next(), scene)
        self.assertEqual(cooperation["cooperator"], {"decision": cooperator})
        self.assertEqual(cooperation["autonomous"], {"decision": b.ACTIVATE})

    def test_both_factor_streams_are_received(self):
        velocity = self.operator.subscribe(b.VELOCITY)
        steering = self.operator.subscribe(b.STEERING)
        # Without scenes: empty arrays in the map frame, at once and then periodically.
        for recorder in (velocity, steering):
            first, second = recorder.at(0), recorder.at(1)
            self.assertEqual(first["factors"], [])
            self.assertEqual(first["header"]["frame_id"], "map")
            stamps = [(m["header"]["stamp"]["sec"], m["header"]["stamp"]["nanosec"])
                      for m in (first, second)]
            self.assertLessEqual(stamps[0], stamps[1])
        # A velocity scene and a steering scene, each in its own stream.
        crossing = b.module(self, self.server.port, "crosswalk")
        turning = b.module(self, self.server.port, "lane_change_right")
        walk, lane = b.new_uuid(), b.new_uuid()
        crossing.sync([b.status(walk, start=12.5, finish=12.5)])
        turning.sync([b.status(lane, start=3.0, finish=40.0)])
        seen = velocity.wait(lambda m: b.factor_of(m, walk))
        self.assertEqual(b.factor_of(seen, walk)["behavior"], "crosswalk")
        self.assertIsNone(b.factor_of(seen, lane))
        seen = steering.wait(lambda m: b.factor_of(m, lane))
        self.assertEqual(b.factor_of(seen, lane)["behavior"], "lane-change")
        self.assertEqual(b.factor_of(seen, lane)["direction"], b.RIGHT)
        self.assertIsNone(b.factor_of(seen, walk))
        # Unsubscribed, a stream stops; the other goes on. roslibpy drops its own listener
        # at once, so a listener of its own is installed as the next answer arrives: the node
        # read the unsubscribe before that call, and sends nothing of the stream after it.
        velocity.topic.unsubscribe()
        late = []
        self.operator.call_ok(
            b.GET_POLICIES, {},
            mark=lambda: self.operator.ros.on(b.VELOCITY[0], late.append))
        steering.at(steering.count() + 2)
        self.assertEqual(late, [])

if __name__ == "__main__":
    unittest.main()
