"""The checks of the stack test, in the order they run; each returns its problems (an empty
list: passed). They share one world: the scenes of one check are still there in the next.
"""

import os
import subprocess
import time
from pathlib import Path

from ros2_peer.dds import new_uuid, uuid_text
from ros2_peer.messages import PARAMETER_ERROR

from .planner import Scene
from .upstream import FAILED, RUNNING, WAITING
from .world import LEFT, steering_factor, velocity_factor
from .world import ACTIVATE, AUTONOMOUS, DEACTIVATE, OPTIONAL, REQUIRED, UNDECIDED

SERVICE_TIMEOUT = 50002
# How long a factor showing a change is waited for: a planner cycle, the node's turn and a
# publication, with room.
SHOWN = 3.0


def say(text):
    print(f"  | {text}", flush=True)


def calls_made(world):
    return {name: len(i.calls) for name, i in world.interfaces.items()}


def agreement(world):
    """Every shown scene of every interface: the module drives as the AD API shows
    (`[COOP-RELAY-FOLLOW.1]`), once the node and the modules are quiet."""
    policies = world.policies()
    if policies is None:
        return ["get_policies: no reply"]
    problems = []
    for name, interface in world.interfaces.items():
        for scene in interface.scenes:
            merged = world.merged(name, scene, policies)
            if merged is None:
                continue
            if interface.activated.get(scene) != merged:
                problems.append(f"{name} {uuid_text(scene)}: the module drives "
                                f"{interface.activated.get(scene)}, the AD API shows {merged}")
    return problems


def settled_agreement(world, timeout=SHOWN):
    """`agreement`, once it holds or `timeout` s have passed."""
    world.wait(lambda: not agreement(world), timeout)
    return agreement(world)


# The panel's browser run, in server/panel/test/.
PANEL_RUN = Path(__file__).resolve().parents[2] / "server" / "panel" / "test" / "stack.mjs"


class Stack:
    def __init__(self, world, panel=None):
        self.world = world
        self.panel_url = panel
        self.lane = world.interfaces["lane_change_left"]
        self.avoid = world.interfaces["static_obstacle_avoidance_left"]
        self.junction = world.interfaces["intersection"]
        self.light = world.interfaces["virtual_traffic_light"]
        self.added = world.interfaces["dynamic_obstacle_avoidance"]
        self.first = new_uuid()

    def matched(self):
        missing = self.world.unmatched()
        if missing:
            self.world.wait(lambda: not self.world.unmatched(), 20.0)
        return self.world.unmatched()

    def design_sequence(self):
        """The design page's sequence, over upstream's endpoints, printed as it runs."""
        w, lane, scene = self.world, self.lane, self.first
        problems = []
        say(f"1. lane_change_left creates scene {uuid_text(scene)} approaching a lane change")
        say("2. its module decision: deactivate (an obstacle): safe = false")
        lane.scenes[scene] = Scene(scene, False, WAITING, 40.0, 120.0)
        if not w.wait(lambda: w.shown("lane_change_left", scene) is not None, SHOWN):
            return ["the scene is not in /api/planning/steering_factors"]
        shown = w.shown("lane_change_left", scene)
        say(f"3-4. the module drives with is_activated = {lane.activated.get(scene)} "
            "(no operator decision: the module's)")
        say(f"5-6. the operator sees it: autonomous {shown.autonomous.decision}, cooperator "
            f"{shown.cooperator.decision}, cancellable {shown.cancellable}")
        if (shown.autonomous.decision, shown.cooperator.decision) != (DEACTIVATE, UNDECIDED):
            problems.append(f"shown {shown}, not deactivate / none")
        if lane.activated.get(scene) is not False:
            problems.append("the module drives activated before any operator decision")
        say("7. the operator sends set_commands: activate")
        reply = w.command(scene, ACTIVATE)
        if reply is None or not reply.status.success:
            return problems + [f"set_commands: {reply and reply.status}"]
        say(f"   answered success = {reply.status.success}")
        status = lane.rtc.find(scene)
        say(f"8. the module's interface holds command {status.command_status.type} "
            f"(ACTIVATE = 1), auto_mode {status.auto_mode}")
        if not w.wait(lambda: lane.activated.get(scene) is True, SHOWN):
            problems.append("is_activated never became true")
        say(f"9-10. module decision still deactivate; is_activated = {lane.activated.get(scene)}")
        lane.scenes[scene].state = RUNNING
        say("11. the module changes lanes: it reports RUNNING")
        if not w.wait(lambda: (s := w.shown("lane_change_left", scene)) is not None
                      and s.cooperator.decision == ACTIVATE, SHOWN):
            problems.append("the AD API does not show the operator's activate")
        else:
            say("    the AD API shows cooperator activate")
        return problems + settled_agreement(w)

    def one_factor_stream(self):
        """default_adapi's factors, remapped, come out on the AD API's topics with the RTC
        scenes' statuses filled in; the node is their only publisher; when default_adapi stops,
        the scenes' own factors remain."""
        w, adapi, junction = self.world, self.world.adapi, self.junction
        scene = new_uuid()
        junction.scenes[scene] = Scene(scene, True, WAITING, 30.0, 30.0)
        lane_start = self.lane.scenes[self.first].start
        adapi.velocity = [
            velocity_factor("crosswalk", 12.0), velocity_factor("intersection", 30.3),
            velocity_factor("stop-sign", 50.0),
        ]
        adapi.steering = [steering_factor("lane-change", LEFT, lane_start + 0.2)]

        def merged():
            v, s = w.operator.velocity.newest(), w.operator.steering.newest()
            if v is None or s is None:
                return None
            return v, s

        def filled():
            got = merged()
            if got is None:
                return False
            v, s = got
            with_status = [f for f in v.factors if f.cooperation
                           and bytes(f.cooperation[0].uuid.uuid) == scene]
            lane = [f for f in s.factors if f.cooperation
                    and bytes(f.cooperation[0].uuid.uuid) == self.first]
            return (len(v.factors) == 3 and len(with_status) == 1
                    and with_status[0].detail == "default_adapi" and len(lane) == 1
                    and lane[0].detail == "default_adapi")

        problems = []
        if not w.wait(filled, SHOWN):
            v, s = merged() or (None, None)

            def listed(array):
                return array and [(f.behavior, f.distance, f.detail, len(f.cooperation))
                                  for f in array.factors]
            problems.append(f"velocity {listed(v)}; steering {listed(s)}")
        else:
            v, _ = merged()
            say("velocity factors: " + ", ".join(
                f"{f.behavior} {f.distance} m ({f.detail}"
                + (f", scene {uuid_text(f.cooperation[0].uuid.uuid)[:8]})" if f.cooperation
                   else ")") for f in v.factors))
        for stream in (w.operator.velocity, w.operator.steering):
            writers = stream.reader.get_subscription_matched_status().current_count
            if writers != 1:
                problems.append(f"{stream.topic} has {writers} publishers")
        adapi.running = False
        started = time.monotonic()

        def only_scenes():
            got = merged()
            return got is not None and all(f.cooperation for f in got[0].factors) \
                and w.shown("intersection", scene) is not None
        if not w.wait(only_scenes, 2.0 + SHOWN):
            problems.append("default_adapi's factors still published after it stopped")
        else:
            say(f"default_adapi stopped: {time.monotonic() - started:.1f} s later only the "
                "scenes' own factors remain")
        adapi.velocity, adapi.steering = [], []
        return problems

    def refused_by_the_core(self):
        """Commands the core refuses reach no module: an unknown scene, and a per-scene
        autonomous, which no upstream module can take."""
        w = self.world
        before = calls_made(w)
        problems = []
        reply = w.command(new_uuid(), ACTIVATE)
        if reply is None or reply.status.success or reply.status.code != PARAMETER_ERROR:
            problems.append(f"unknown scene: {reply and reply.status}")
        reply = w.command(self.first, AUTONOMOUS)
        if reply is None or reply.status.success or reply.status.code != PARAMETER_ERROR:
            problems.append(f"autonomous: {reply and reply.status}")
        else:
            say(f"autonomous refused: {reply.status.message}")
        w.settle(0.3)
        if calls_made(w) != before:
            problems.append(f"calls reached modules: {before} -> {calls_made(w)}")
        return problems

    def refused_forward(self):
        """A module that refuses a command (its scene failed before the node heard of it): the
        answer names it, and the AD API does not show the refused decision."""
        w, lane = self.world, self.lane
        scene = new_uuid()
        lane.scenes[scene] = Scene(scene, True, WAITING, 60.0, 150.0)
        if not w.wait(lambda: w.shown("lane_change_left", scene) is not None, SHOWN):
            return ["the scene is not shown"]
        lane.silent = True
        lane.scenes[scene].state = FAILED
        w.settle(0.25)
        reply = w.command(scene, DEACTIVATE)
        problems = []
        if reply is None or reply.status.success or reply.status.code != PARAMETER_ERROR \
                or "lane_change_left" not in reply.status.message:
            problems.append(f"answer {reply and reply.status}")
        else:
            say(f"answered: {reply.status.message}")
        shown = w.shown("lane_change_left", scene)
        if shown is not None and shown.cooperator.decision == DEACTIVATE:
            problems.append("the AD API shows the refused deactivate")
        lane.silent = False
        del lane.scenes[scene]
        return problems + settled_agreement(w)

    def silent_module(self):
        """A module that stops answering: the answer names it after the deadline; one that
        stops publishing: its scenes age out."""
        w, junction = self.world, self.junction
        scene = new_uuid()
        junction.scenes[scene] = Scene(scene, True, WAITING, 30.0, 30.0)
        if not w.wait(lambda: w.shown("intersection", scene) is not None, SHOWN):
            return ["the scene is not shown"]
        junction.mute = True
        started = time.monotonic()
        reply = w.command(scene, DEACTIVATE, )
        took = time.monotonic() - started
        problems = []
        if reply is None or reply.status.success or reply.status.code != SERVICE_TIMEOUT \
                or "intersection" not in reply.status.message:
            problems.append(f"answer {reply and reply.status}")
        else:
            say(f"answered after {took:.2f} s: {reply.status.message}")
        shown = w.shown("intersection", scene)
        if shown is None or shown.cooperator.decision == DEACTIVATE:
            problems.append(f"shown {shown}: not the scene without the unanswered deactivate")
        junction.silent = True
        started = time.monotonic()
        if not w.wait(lambda: w.shown("intersection", scene) is None, 14.0):
            problems.append("the silent module's scene is still shown after 14 s")
        else:
            took = time.monotonic() - started
            say(f"the silent module's scene left the factors after {took:.1f} s")
        junction.mute = junction.silent = False
        junction.scenes.clear()
        junction.rtc.clear()
        # Answers to the calls it left unanswered arrive now: past their deadlines, not taken.
        w.settle(0.3)
        return problems

    def restart(self):
        """A module that restarts with new identifiers: the old scene leaves, commands for it
        are refused and reach no module, the new one is shown without a decision."""
        w, lane = self.world, self.lane
        old = self.first
        new = new_uuid()
        lane.rtc.clear()
        lane.scenes = {new: Scene(new, False, WAITING, 35.0, 110.0)}
        problems = []
        if not w.wait(lambda: w.shown("lane_change_left", old) is None
                      and w.shown("lane_change_left", new) is not None, SHOWN):
            return ["the factors do not show the new scene in place of the old"]
        shown = w.shown("lane_change_left", new)
        if shown.cooperator.decision != UNDECIDED:
            problems.append(f"the new scene shows cooperator {shown.cooperator.decision}")
        before = calls_made(w)
        reply = w.command(old, ACTIVATE)
        if reply is None or reply.status.success:
            problems.append(f"a command for the old scene: {reply and reply.status}")
        w.settle(0.3)
        if calls_made(w) != before:
            problems.append("a command for the old scene reached a module")
        self.first = new
        return problems + settled_agreement(w)

    def policy_toggle(self):
        """A policy toggle with standing operator decisions: upstream's auto-mode switch
        overwrites them, the node sends them again, and each module drives as the AD API shows.
        On behavior_velocity_planner's intersection only the node restores the decision; on
        behavior_path_planner's lane_change_left the commands its interface stored while locked
        are applied again at every unlock too (upstream's stale stored commands)."""
        w = self.world
        problems = []
        scene = new_uuid()
        self.junction.scenes[scene] = Scene(scene, False, WAITING, 25.0, 25.0)
        if not w.wait(lambda: w.shown("intersection", scene) is not None, SHOWN):
            return ["the intersection scene is not shown"]
        for name, behavior, standing in (("intersection", "intersection", scene),
                                         ("lane_change_left", "lane-change", self.first)):
            problems += self.toggle(name, behavior, standing)
        return problems

    def toggle(self, name, behavior, scene):
        w, interface = self.world, self.world.interfaces[name]
        problems = []
        reply = w.command(scene, ACTIVATE)
        if reply is None or not reply.status.success:
            return [f"{name}: set_commands: {reply and reply.status}"]
        for policy in (REQUIRED, OPTIONAL):
            start = len(interface.calls)
            reply = w.policy(behavior, policy)
            if reply is None or not reply.status.success:
                problems.append(f"{name}: set_policies {policy}: {reply and reply.status}")
                continue
            w.settle(0.4)
            calls = interface.calls[start:]
            say(f"{behavior} {'required' if policy == REQUIRED else 'optional'}: {name} was "
                f"called {[(kind, v if kind == 'auto_mode' else len(v)) for kind, v in calls]}")
            if ("auto_mode", policy == OPTIONAL) not in calls:
                problems.append(f"{name}: no enable_auto_mode({policy == OPTIONAL}) call")
            problems += settled_agreement(w)
        status = interface.rtc.find(scene)
        if status is None or status.auto_mode or status.command_status.type != 1:
            problems.append(f"{name}: the standing activate is lost at the module: {status}")
        if interface.activated.get(scene) is not True:
            problems.append(f"{name}: the module does not drive with the standing activate")
        return problems

    def none_is_not_deactivate(self):
        """Under a required policy upstream registers a new scene with command DEACTIVATE: the
        AD API shows no operator decision (none), and the module waits, as required says."""
        w, avoid = self.world, self.avoid
        # One auto-mode switch for both sequences: a split is refused ([COOP-RELAY-POLICY.1]).
        reply = w.policy("avoidance", REQUIRED, ["change"])
        if reply is None or reply.status.success or reply.status.code != PARAMETER_ERROR:
            return [f"set_policies of one sequence: {reply and reply.status}"]
        say(f"one sequence alone refused: {reply.status.message}")
        reply = w.policy("avoidance", REQUIRED, ["change", "return"])
        if reply is None or not reply.status.success:
            return [f"set_policies: {reply and reply.status}"]
        w.settle(0.4)
        scene = new_uuid()
        avoid.scenes[scene] = Scene(scene, True, WAITING, 20.0, 60.0)
        problems = []
        if not w.wait(lambda: w.shown("static_obstacle_avoidance_left", scene) is not None, SHOWN):
            return ["the scene is not shown"]
        status = avoid.rtc.find(scene)
        shown = w.shown("static_obstacle_avoidance_left", scene)
        say(f"the module holds command {status.command_status.type} (DEACTIVATE = 0), auto_mode "
            f"{status.auto_mode}; the AD API shows cooperator {shown.cooperator.decision} "
            f"(none = {UNDECIDED})")
        if shown.cooperator.decision != UNDECIDED:
            problems.append("the AD API shows an operator decision nobody made")
        problems += settled_agreement(w)
        reply = w.policy("avoidance", OPTIONAL, ["change", "return"])
        if reply is None or not reply.status.success:
            problems.append(f"set_policies back: {reply and reply.status}")
        return problems + settled_agreement(w)

    def added_interface(self):
        """An interface no standard binding has, added by the node's settings: its scene shows
        under its behaviour, and a command reaches its own service."""
        w, added = self.world, self.added
        scene = new_uuid()
        added.scenes[scene] = Scene(scene, False, WAITING, 35.0, 70.0)
        if not w.wait(lambda: w.shown("dynamic_obstacle_avoidance", scene) is not None, SHOWN):
            return ["the scene is not in /api/planning/steering_factors"]
        factor = next(f for f in w.operator.steering.newest().factors
                      if f.cooperation and bytes(f.cooperation[0].uuid.uuid) == scene)
        say(f"shown as a steering factor of behaviour {factor.behavior!r}")
        problems = [] if factor.behavior == "dynamic-avoidance" else [
            f"behaviour {factor.behavior!r}, not the settings' dynamic-avoidance"]
        reply = w.command(scene, ACTIVATE)
        if reply is None or not reply.status.success:
            problems.append(f"set_commands: {reply and reply.status}")
        if not any(kind == "commands" for kind, _ in added.calls):
            problems.append("dynamic_obstacle_avoidance's service was not called")
        if not w.wait(lambda: added.activated.get(scene) is True, SHOWN):
            problems.append("the module does not drive activated")
        problems += settled_agreement(w)
        del added.scenes[scene]
        added.rtc.remove(scene)
        return problems

    def panel(self):
        """The operator panel, served by the same node, in headless Chromium: it shows a scene
        of upstream's intersection interface, its operator's confirmed activate reaches the
        module, which drives with it, and the AD API over DDS shows it; the panel does not offer
        the decisions no upstream interface can take (`server/panel/test/stack.mjs`)."""
        if self.panel_url is None:
            return ["no --panel URL: the node serves no panel"]
        w, junction = self.world, self.junction
        scene = new_uuid()
        junction.scenes[scene] = Scene(scene, False, WAITING, 45.0, 45.0)
        if not w.wait(lambda: w.shown("intersection", scene) is not None, SHOWN):
            return ["the scene is not shown"]
        commands = len([c for c in junction.calls if c[0] == "commands"])
        with open(Path(os.environ.get("STACK_TEST_OUT", ".")) / "panel.log", "w+") as log:
            run = subprocess.Popen(["node", str(PANEL_RUN), self.panel_url, scene.hex()],
                                   cwd=PANEL_RUN.parent.parent, stdout=log,
                                   stderr=subprocess.STDOUT)
            # The planners keep their cycles while the browser works.
            ended = w.wait(lambda: run.poll() is not None, 90.0)
            if not ended:
                run.kill()
                run.wait()
            log.seek(0)
            for line in log.read().splitlines():
                say(f"panel: {line}")
        problems = []
        if not ended or run.returncode != 0:
            problems.append(f"the panel's run failed (exit status {run.returncode})")
        if not any(c[0] == "commands" for c in junction.calls[commands:]):
            problems.append("the panel's activate reached no module")
        if not w.wait(lambda: junction.activated.get(scene) is True, SHOWN):
            problems.append("the module does not drive activated after the panel's activate")
        status = junction.rtc.find(scene)
        say(f"the module holds command {status.command_status.type} (ACTIVATE = 1) and drives "
            f"with is_activated = {junction.activated.get(scene)}")
        shown = w.shown("intersection", scene)
        if shown is None or shown.cooperator.decision != ACTIVATE:
            problems.append(f"the AD API over DDS shows {shown}, not the panel's activate")
        problems += settled_agreement(w)
        del junction.scenes[scene]
        junction.rtc.remove(scene)
        return problems

    def undefined_state(self):
        """Upstream takes any state from RUNNING, 7 included: the module's arrays are then
        refused whole (logged by the node, checked by tools/stack-test), its scenes stay as last
        shown, and no other module's scenes are harmed."""
        w, lane, junction = self.world, self.lane, self.junction
        scene, other = new_uuid(), new_uuid()
        lane.scenes[scene] = Scene(scene, True, RUNNING, 70.0, 160.0)
        junction.scenes[other] = Scene(other, True, WAITING, 45.0, 45.0)
        if not w.wait(lambda: w.shown("lane_change_left", scene) is not None
                      and w.shown("intersection", other) is not None, SHOWN):
            return ["the scenes are not shown"]
        # Registered waiting, then running, then 7.
        for state in (RUNNING, 7):
            lane.scenes[scene].state = state
            if not w.wait(lambda: lane.rtc.find(scene).state.type == state, SHOWN):
                return [f"the module did not take state {state}"]
        say(f"lane_change_left holds scene {uuid_text(scene)[:8]} in state "
            f"{lane.rtc.find(scene).state.type} and publishes it")
        problems = []
        reply = w.command(other, DEACTIVATE)
        if reply is None or not reply.status.success:
            problems.append(f"the intersection's command: {reply and reply.status}")
        elif not w.wait(lambda: (s := w.shown("intersection", other)) is not None
                        and s.cooperator.decision == DEACTIVATE, SHOWN):
            problems.append("the intersection's scene does not show the operator's deactivate")
        w.settle(0.6)  # a few more broken arrays
        if w.shown("lane_change_left", scene) is None:
            problems.append("the lane change's scene left before its time to live")
        # The module drops the broken scene; its arrays are taken again.
        del lane.scenes[scene]
        lane.rtc.remove(scene)
        if not w.wait(lambda: w.shown("lane_change_left", scene) is None, SHOWN):
            problems.append("the lane change's scene is still shown after the module removed it")
        del junction.scenes[other]
        junction.rtc.remove(other)
        return problems

    def virtual_traffic_light(self):
        """virtual_traffic_light's statuses say TRAFFIC_LIGHT: a command still reaches its own
        service (upstream's controller routes by module type and cannot)."""
        w, light = self.world, self.light
        scene = new_uuid()
        light.scenes[scene] = Scene(scene, False, WAITING, 15.0, 15.0)
        if not w.wait(lambda: w.shown("virtual_traffic_light", scene) is not None, SHOWN):
            return ["the scene is not shown"]
        reply = w.command(scene, ACTIVATE)
        problems = []
        if reply is None or not reply.status.success:
            problems.append(f"set_commands: {reply and reply.status}")
        if not any(kind == "commands" for kind, _ in light.calls):
            problems.append("virtual_traffic_light's service was not called")
        return problems + settled_agreement(w)

    ORDER = [
        ("every endpoint of the two planners and the operator matched the node's", "matched"),
        ("the design page's sequence, through lane_change_left's own endpoints", "design_sequence"),
        ("one factor stream: default_adapi's factors with the scenes' statuses",
         "one_factor_stream"),
        ("commands the core refuses reach no module", "refused_by_the_core"),
        ("a command a module refuses: the answer names it, nothing shown", "refused_forward"),
        ("a module that stops answering, then stops publishing", "silent_module"),
        ("a module restarting with new identifiers", "restart"),
        ("a policy toggle keeps the standing operator decisions", "policy_toggle"),
        ("a new scene under required: none, not deactivate", "none_is_not_deactivate"),
        ("virtual_traffic_light reached by its own service", "virtual_traffic_light"),
        ("an interface the node's settings add reaches its module", "added_interface"),
        ("the operator panel on the same node, in headless Chromium", "panel"),
        ("an undefined state refuses one module's arrays, no other's", "undefined_state"),
    ]
