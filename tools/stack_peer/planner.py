"""Planner processes as a stock Autoware stack runs them, each a DDS participant of its own with
upstream's `rtc_interface` per module (`upstream.py`), on upstream's endpoints (§3.2): the
status array and the auto-mode status published with depth 1, reliable and volatile; the two
services with ROS 2's default service QoS, answering with the request header copied.

A planner runs a cycle every 100 ms, as the planners do: it reports each scene it plans
(`update`), records what each scene's `is_activated` says (what the module drives with), ages
out statuses older than 10 s and publishes every interface's array and auto mode.
behavior_path_planner locks every interface around its modules' run and takes the service
calls that arrive meanwhile (stored, applied at the unlock: §6 items 13 to 16);
behavior_velocity_planner has no lock and answers at once.
"""

import time

from cdr_golden import Time

from .upstream import (
    AutoModeCall,
    AutoModeReply,
    AutoModeStatus,
    CommandsCall,
    CommandsReply,
    CooperateStatusArray,
    RtcInterface,
)

CYCLE = 0.1


def stamp_now():
    now = time.time()
    return Time(int(now), int((now % 1) * 1e9))


class Scene:
    """What the module plans for one scene: its report's fields."""

    def __init__(self, uuid, safe, state, start, finish, requested=False):
        self.uuid, self.safe, self.state = uuid, safe, state
        self.start, self.finish, self.requested = start, finish, requested


class Interface:
    def __init__(self, planner, name, module, enable_rtc):
        from cyclonedds.pub import DataWriter
        from cyclonedds.sub import DataReader
        from cyclonedds.topic import Topic

        self.rtc = RtcInterface(name, module, enable_rtc)
        self.name = name
        self.scenes = {}  # uuid → Scene: what the module reports each cycle
        self.activated = {}  # uuid → what is_activated said at the last cycle
        self.silent = False  # stops publishing (a module that hangs)
        self.mute = False  # stops answering its services
        self.calls = []  # ("commands", [CooperateCommand]) or ("auto_mode", enable), in order
        dp, topic_qos, service_qos = planner.participant, planner.topic_qos, planner.service_qos
        self.status_writer = DataWriter(
            dp, Topic(dp, f"rt/planning/cooperate_status/{name}", CooperateStatusArray), topic_qos)
        self.auto_mode_writer = DataWriter(
            dp, Topic(dp, f"rt/planning/auto_mode_status/{name}", AutoModeStatus), topic_qos)
        commands = f"/planning/cooperate_commands/{name}"
        auto_mode = f"/planning/enable_auto_mode/{name}"
        self.commands_reader = DataReader(
            dp, Topic(dp, f"rq{commands}Request", CommandsCall), service_qos)
        self.commands_writer = DataWriter(
            dp, Topic(dp, f"rr{commands}Reply", CommandsReply), service_qos)
        self.auto_mode_reader = DataReader(
            dp, Topic(dp, f"rq{auto_mode}Request", AutoModeCall), service_qos)
        self.auto_mode_writer_reply = DataWriter(
            dp, Topic(dp, f"rr{auto_mode}Reply", AutoModeReply), service_qos)

    def matched(self):
        """Whether the node reads both topics and calls both services."""
        return all(e.get_publication_matched_status().current_count > 0 for e in (
            self.status_writer, self.auto_mode_writer, self.commands_writer,
            self.auto_mode_writer_reply)) and all(
            e.get_subscription_matched_status().current_count > 0
            for e in (self.commands_reader, self.auto_mode_reader))

    def serve(self):
        if self.mute:
            return
        for call in self.commands_reader.take(N=20):
            if not isinstance(call, CommandsCall):
                continue
            self.calls.append(("commands", list(call.commands)))
            responses = self.rtc.on_commands(call.commands)
            self.commands_writer.write(CommandsReply(call.guid, call.seq, responses))
        for call in self.auto_mode_reader.take(N=20):
            if not isinstance(call, AutoModeCall):
                continue
            self.calls.append(("auto_mode", call.enable))
            success = self.rtc.on_auto_mode(call.enable)
            self.auto_mode_writer_reply.write(AutoModeReply(call.guid, call.seq, success))

    def plan(self, stamp):
        for scene in self.scenes.values():
            self.rtc.update(scene.uuid, scene.safe, scene.state, scene.start, scene.finish, stamp,
                            scene.requested)
        self.activated = {uuid: self.rtc.is_activated(uuid) for uuid in self.scenes}

    def publish(self, stamp):
        self.rtc.remove_expired(stamp)
        if not self.silent:
            self.status_writer.write(self.rtc.array(stamp))
            self.auto_mode_writer.write(self.rtc.auto_mode_status())


class Planner:
    """One planner process: a participant and its interfaces."""

    def __init__(self, domain, name, interfaces, locks):
        from cyclonedds.core import Policy, Qos
        from cyclonedds.domain import DomainParticipant
        from cyclonedds.util import duration

        self.name = name
        self.locks = locks
        self.participant = DomainParticipant(domain)
        reliable = Policy.Reliability.Reliable(duration(seconds=1))
        self.topic_qos = Qos(reliable, Policy.Durability.Volatile, Policy.History.KeepLast(1))
        self.service_qos = Qos(reliable, Policy.Durability.Volatile, Policy.History.KeepLast(10))
        self.interfaces = {
            name: Interface(self, name, module, enable_rtc)
            for name, module, enable_rtc in interfaces
        }
        self.next_cycle = 0.0

    def pump(self):
        """Serves calls, and runs a cycle when one is due."""
        if not self.locks:
            for interface in self.interfaces.values():
                interface.serve()
        now = time.monotonic()
        if now < self.next_cycle:
            return
        self.next_cycle = now + CYCLE
        stamp = stamp_now()
        for interface in self.interfaces.values():
            if self.locks:
                interface.rtc.lock()
                # The calls that came while the modules ran: stored, not applied.
                interface.serve()
            interface.plan(stamp)
            if self.locks:
                interface.rtc.unlock()
            interface.publish(stamp)
