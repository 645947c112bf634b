"""The checks of the node as the peer finds it: in the ROS graph, its two topics before any
scene, its default policies, and the scenes a module first reports through sync. `Scenes` holds
the run's scenes, which the later checks (`checks_requests.py`) go on with.
"""

import time

from .dds import (
    CONFIGURED,
    DISCOVERY_INFO,
    GET_POLICIES,
    SET_COMMANDS,
    SET_POLICIES,
    STEERING,
    SYNC,
    VELOCITY,
    bounded,
    new_uuid,
    report,
)
from .matching import (
    RecentStamp,
    diff,
    factors_problems,
    no_reply,
    node_status,
    steering_factor,
    sync_answer,
    sync_problems,
    velocity_factor,
)
from .messages import (
    ACTIVATE,
    DEACTIVATE,
    LEFT,
    MODULE_AVOIDANCE_RIGHT,
    MODULE_CROSSWALK,
    MODULE_INTERSECTION,
    MODULE_LANE_CHANGE_LEFT,
    OPTIONAL,
    RIGHT,
    RTC_DEACTIVATE,
    RUNNING,
    SUCCESS,
    UNDECIDED,
    WAITING,
    Activation,
    Header,
    StatedSequence,
    SteeringFactorArray,
    UUID,
    VelocityFactorArray,
)


def check_graph(peer, checks):
    """The node in the ROS graph: `ros_discovery_info`."""
    found = {}

    def named():
        message = peer.graph.wait(
            lambda m: any(n.node_name == "cooperation" and n.node_namespace == "/"
                          for n in m.node_entities_info_seq), 5.0)
        if message is None:
            newest = peer.graph.newest()
            seen = [(n.node_namespace, n.node_name) for n in newest.node_entities_info_seq] \
                if newest else None
            errors = f"; reader errors: {peer.graph.errors[-2:]}" if peer.graph.errors else ""
            return [f"no {DISCOVERY_INFO} sample naming node \"cooperation\" in \"/\" within 5 s "
                    f"(newest names {seen}){errors}"]
        # The newest sample of the node's participant: it lists every entity made by now.
        mine = [m for _, m in peer.graph.samples if bytes(m.gid.data) == bytes(message.gid.data)]
        found["info"] = mine[-1]
        return None

    checks.run(f"graph: {DISCOVERY_INFO} names node \"cooperation\" in namespace \"/\"", named)

    def node_endpoints():
        """The node's participant and endpoints, from DDS discovery (the participant owning
        the velocity factors' writer)."""
        deadline = time.monotonic() + bounded(3.0)
        while True:
            participants, publications, subscriptions = peer.discovered()
            writer = next((p for p in publications.values() if p.topic_name == VELOCITY), None)
            if writer is not None or time.monotonic() >= deadline:
                break
            time.sleep(0.05)
        if writer is None:
            return None
        owner = writer.participant_key.bytes
        writers = {p.topic_name: k for k, p in publications.items()
                   if p.participant_key.bytes == owner}
        readers = {s.topic_name: k for k, s in subscriptions.items()
                   if s.participant_key.bytes == owner}
        return owner, writers, readers

    def gid():
        info = found.get("info")
        if info is None:
            return ["no sample to check"]
        endpoints = node_endpoints()
        if endpoints is None:
            return [f"no participant with a writer on {VELOCITY} was discovered"]
        owner, _, _ = endpoints
        data = bytes(info.gid.data)
        expected = owner + bytes(peer.gid_len - 16)
        if data != expected:
            return [f"gid {data.hex()}, expected the participant's GUID {expected.hex()}"]
        return None

    checks.run(f"graph: the {DISCOVERY_INFO} gid is the node's participant GUID", gid)

    def entities():
        info = found.get("info")
        if info is None:
            return ["no sample to check"]
        endpoints = node_endpoints()
        if endpoints is None:
            return [f"no participant with a writer on {VELOCITY} was discovered"]
        _, writers, readers = endpoints
        node = next(n for n in info.node_entities_info_seq
                    if n.node_name == "cooperation" and n.node_namespace == "/")
        pad = bytes(peer.gid_len - 16)
        listed_writers = {bytes(g.data) for g in node.writer_gid_seq}
        listed_readers = {bytes(g.data) for g in node.reader_gid_seq}
        problems = []
        wanted_writers = [VELOCITY, STEERING] + [
            f"rr{s}Reply" for s in (SET_COMMANDS, SET_POLICIES, GET_POLICIES, SYNC)]
        wanted_readers = [f"rq{s}Request" for s in (SET_COMMANDS, SET_POLICIES, GET_POLICIES, SYNC)]
        for topic in wanted_writers:
            if topic not in writers:
                problems.append(f"no writer of the node on {topic} was discovered")
            elif writers[topic] + pad not in listed_writers:
                problems.append(f"writer {writers[topic].hex()} ({topic}) not in writer_gid_seq")
        for topic in wanted_readers:
            if topic not in readers:
                problems.append(f"no reader of the node on {topic} was discovered")
            elif readers[topic] + pad not in listed_readers:
                problems.append(f"reader {readers[topic].hex()} ({topic}) not in reader_gid_seq")
        for data in listed_writers | listed_readers:
            if len(data) != peer.gid_len or data[16:] != pad:
                problems.append(f"gid {data.hex()} is not a GUID padded to {peer.gid_len} bytes")
        return problems

    checks.run("graph: the node's gids list its topic and service readers and writers", entities)


def check_streams_at_start(peer, checks):
    """Both topics, before any scene: empty arrays in the map frame, at 10 Hz."""
    for stream, data_type in ((peer.velocity, VelocityFactorArray),
                              (peer.steering, SteeringFactorArray)):
        checks.run(
            f"{stream.topic}: published with no scene: no factors, frame \"map\", current stamp",
            lambda stream=stream, data_type=data_type: (
                ["nothing received within 2 s"] if (m := stream.next(2.0)) is None
                else diff(data_type(Header(RecentStamp(), "map"), []), m, stream.topic)))

    window = 2.0
    start = time.monotonic()
    while time.monotonic() - start < bounded(window):
        peer.pump()
        time.sleep(0.01)
    end = time.monotonic()
    for stream in (peer.velocity, peer.steering):
        def rate(stream=stream):
            taken = [m for t, m in stream.samples if start < t <= end]
            per_second = len(taken) / window
            problems = []
            if not 7.0 <= per_second <= 14.0:
                problems.append(f"{len(taken)} publications in {window} s ({per_second:.1f} Hz)")
            stamps = [(m.header.stamp.sec, m.header.stamp.nanosec) for m in taken]
            if stamps != sorted(stamps):
                problems.append(f"stamps go backwards: {stamps}")
            return problems

        checks.run(f"{stream.topic}: published periodically at 10 Hz, stamps never backwards",
                   rate)


def check_get_policies(peer, checks):
    def default():
        reply = peer.get_policies.call(0)
        if reply is None:
            return [no_reply(peer.get_policies)]
        problems = diff(SUCCESS, reply.status, "status")
        listed = [(p.behavior, p.sequence) for p in reply.policies]
        if len(listed) != len(set(listed)):
            problems.append(f"a module listed twice: {listed}")
        if set(listed) != CONFIGURED:
            problems.append(f"missing {sorted(CONFIGURED - set(listed))}, "
                            f"extra {sorted(set(listed) - CONFIGURED)}")
        others = [(p.behavior, p.sequence, p.policy) for p in reply.policies
                  if p.policy != OPTIONAL]
        if others:
            problems.append(f"not optional, as config/cooperation.param.yaml says: {others}")
        return problems

    checks.run("get_policies: every module of config/cooperation.param.yaml, each optional",
               default)


class Scenes:
    """The scenes the run reports, by role."""

    def __init__(self):
        self.stop = new_uuid()       # intersection, safe, running, 35.25 m
        self.walk = new_uuid()       # crosswalk, unsafe, waiting, 12.5 m
        self.turn = new_uuid()       # lane_change_left, unsafe, waiting, 10.5 to 50.75 m
        self.back = new_uuid()       # static_obstacle_avoidance_right, return, safe, running
        self.held = new_uuid()       # intersection under a required policy: the operator's
        self.stray = new_uuid()      # never reported
        # The lane change's last report after the first (safe, state, start, finish).
        self.turn_reported = None


def check_scenes_reported(peer, checks, s):
    """A module's scenes through sync, and every field of both topics showing them."""
    sync = peer.sync

    def intersection():
        reply = sync.call("intersection", [report(s.stop, True, RUNNING, 35.25, 35.25)], [], [])
        return sync_problems(reply, sync_answer(
            [(s.stop, True, "")],
            [node_status(s.stop, MODULE_INTERSECTION, True, RUNNING, 35.25, 35.25,
                         RTC_DEACTIVATE, True)],
            [Activation(UUID(s.stop), True, False, False)]), sync)

    checks.run("sync intersection: a safe running scene registers, activated, auto mode",
               intersection)

    def crosswalk():
        # A velocity scene has one distance, the start: the node reports it as both.
        reply = sync.call("crosswalk", [report(s.walk, False, WAITING, 12.5, 14.0)], [], [])
        return sync_problems(reply, sync_answer(
            [(s.walk, True, "")],
            [node_status(s.walk, MODULE_CROSSWALK, False, WAITING, 12.5, 12.5,
                         RTC_DEACTIVATE, True)],
            [Activation(UUID(s.walk), False, False, False)]), sync)

    checks.run("sync crosswalk: an unsafe waiting scene registers, not activated", crosswalk)

    def lane_change():
        reply = sync.call("lane_change_left", [report(s.turn, False, WAITING, 10.5, 50.75)],
                          [], [])
        return sync_problems(reply, sync_answer(
            [(s.turn, True, "")],
            [node_status(s.turn, MODULE_LANE_CHANGE_LEFT, False, WAITING, 10.5, 50.75,
                         RTC_DEACTIVATE, True)],
            [Activation(UUID(s.turn), False, False, False)]), sync)

    checks.run("sync lane_change_left: a steering scene registers with both distances",
               lane_change)

    def avoidance():
        reply = sync.call("static_obstacle_avoidance_right",
                          [report(s.back, True, RUNNING, 5.0, 30.0)],
                          [StatedSequence(UUID(s.back), "return")], [])
        return sync_problems(reply, sync_answer(
            [(s.back, True, "")],
            [node_status(s.back, MODULE_AVOIDANCE_RIGHT, True, RUNNING, 5.0, 30.0,
                         RTC_DEACTIVATE, True)],
            [Activation(UUID(s.back), True, False, False)]), sync)

    checks.run("sync static_obstacle_avoidance_right: a scene stated in sequence \"return\"",
               avoidance)

    # Nearest first; two factors each, so the second factor's float64 pose follows the first's
    # strings and cooperation entry.
    checks.run(
        f"{VELOCITY}: every field of the crosswalk and intersection scenes, nearest first",
        lambda: factors_problems(peer.velocity, VelocityFactorArray(
            Header(RecentStamp(), "map"),
            [velocity_factor(s.walk, 12.5, "crosswalk", DEACTIVATE, UNDECIDED),
             velocity_factor(s.stop, 35.25, "intersection", ACTIVATE, UNDECIDED)]),
            [s.walk, s.stop]))
    checks.run(
        f"{STEERING}: every field of the avoidance and lane change scenes, nearest first",
        lambda: factors_problems(peer.steering, SteeringFactorArray(
            Header(RecentStamp(), "map"),
            [steering_factor(s.back, 5.0, 30.0, RIGHT, "avoidance", "return", ACTIVATE,
                             UNDECIDED),
             steering_factor(s.turn, 10.5, 50.75, LEFT, "lane-change", "", DEACTIVATE,
                             UNDECIDED)]),
            [s.back, s.turn]))


def refresh(peer, s):
    """Reports the crosswalk, lane change and avoidance scenes again, as they were, so that none
    expires (the settings' ttl_ms, 10 s) while the run goes on; the answers are not checked."""
    peer.sync.call("crosswalk", [report(s.walk, False, WAITING, 12.5, 14.0)], [], [])
    peer.sync.call("static_obstacle_avoidance_right", [report(s.back, True, RUNNING, 5.0, 30.0)],
                   [], [])
    if s.turn_reported:
        peer.sync.call("lane_change_left", [report(s.turn, *s.turn_reported)], [], [])
