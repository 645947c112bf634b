"""The stack around the node: two planner processes (`planner.py`) and an operator, an AD API
client over DDS with the velocity and steering factor readers (the clients and readers of
`tools/ros2_peer/dds.py`). `World.pump` turns every participant once; every wait pumps.
"""

import time

from ros2_peer.dds import (
    GET_POLICIES,
    SET_COMMANDS,
    SET_POLICIES,
    STEERING,
    VELOCITY,
    Client,
    Stream,
    bounded,
)
from ros2_peer.messages import (
    ACTIVATE,
    IDENTITY,
    LEFT,
    Header,
    SteeringFactor,
    VelocityFactor,
    AUTONOMOUS,
    DEACTIVATE,
    OPTIONAL,
    REQUIRED,
    UNDECIDED,
    CooperationCommand,
    CooperationDecision,
    CooperationPolicy,
    GetPoliciesCall,
    GetPoliciesReply,
    SetCommandsCall,
    SetCommandsReply,
    SetPoliciesCall,
    SetPoliciesReply,
    SteeringFactorArray,
    UUID,
    VelocityFactorArray,
)

from .planner import Planner, stamp_now
from .upstream import AVOIDANCE_LEFT, INTERSECTION, LANE_CHANGE_LEFT, NONE, TRAFFIC_LIGHT

# The planners of the test, with upstream's shipped default: enable_rtc false (auto mode on),
# as the node's default policy (optional) says. `dynamic_obstacle_avoidance` is an interface
# no standard binding has: the node binds it because its settings add it (tools/stack-test).
PLANNERS = {
    "behavior_path_planner": (
        [("lane_change_left", LANE_CHANGE_LEFT, False),
         ("static_obstacle_avoidance_left", AVOIDANCE_LEFT, False),
         ("dynamic_obstacle_avoidance", NONE, False)],
        True,
    ),
    "behavior_velocity_planner": (
        [("intersection", INTERSECTION, False),
         ("virtual_traffic_light", TRAFFIC_LIGHT, False)],
        False,
    ),
}

# Each interface's AD API behaviour (the node's bindings) and whether it is a steering factor.
BEHAVIOR = {
    "lane_change_left": ("lane-change", True),
    "static_obstacle_avoidance_left": ("avoidance", True),
    "intersection": ("intersection", False),
    "virtual_traffic_light": ("virtual-traffic-light", False),
    "dynamic_obstacle_avoidance": ("dynamic-avoidance", True),
}


class Operator:
    """The AD API's client: what `Client` and `Stream` need of a peer."""

    def __init__(self, world, domain):
        from cyclonedds.core import Policy, Qos
        from cyclonedds.domain import DomainParticipant
        from cyclonedds.util import duration

        self.world = world
        self.participant = DomainParticipant(domain)
        reliable = Policy.Reliability.Reliable(duration(seconds=1))
        self.service_qos = Qos(reliable, Policy.Durability.Volatile, Policy.History.KeepLast(10))
        stream_qos = Qos(reliable, Policy.Durability.Volatile, Policy.History.KeepLast(100))
        self.velocity = Stream(self, VELOCITY, VelocityFactorArray, stream_qos)
        self.steering = Stream(self, STEERING, SteeringFactorArray, stream_qos)
        self.set_commands = Client(self, SET_COMMANDS, SetCommandsCall, SetCommandsReply)
        self.set_policies = Client(self, SET_POLICIES, SetPoliciesCall, SetPoliciesReply)
        self.get_policies = Client(self, GET_POLICIES, GetPoliciesCall, GetPoliciesReply)
        self.clients = [self.set_commands, self.set_policies, self.get_policies]

    def pump(self):
        self.world.pump()


def velocity_factor(behavior, distance):
    """A factor as default_adapi writes it: no cooperation status."""
    return VelocityFactor(IDENTITY, distance, 1, behavior, "", "default_adapi", [])


def steering_factor(behavior, direction, start):
    return SteeringFactor([IDENTITY, IDENTITY], [start, start + 80.0], direction, 1, behavior, "",
                          "default_adapi", [])


class DefaultAdapi:
    """A stand-in for Autoware's default_adapi: its two factor arrays, at 5 Hz, on the topics
    the launch file remaps its outputs to, with the AD API's QoS (depth 1, reliable, volatile)
    and `cooperation` empty, as upstream leaves it."""

    PERIOD = 0.2

    def __init__(self, domain, velocity_topic, steering_topic):
        from cyclonedds.core import Policy, Qos
        from cyclonedds.domain import DomainParticipant
        from cyclonedds.pub import DataWriter
        from cyclonedds.topic import Topic
        from cyclonedds.util import duration

        self.participant = DomainParticipant(domain)
        qos = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.Durability.Volatile,
                  Policy.History.KeepLast(1))
        dp = self.participant
        self.velocity_writer = DataWriter(
            dp, Topic(dp, "rt" + velocity_topic, VelocityFactorArray), qos)
        self.steering_writer = DataWriter(
            dp, Topic(dp, "rt" + steering_topic, SteeringFactorArray), qos)
        self.velocity = []  # the factors it publishes
        self.steering = []
        self.running = True
        self.next = 0.0

    def matched(self):
        return all(w.get_publication_matched_status().current_count > 0
                   for w in (self.velocity_writer, self.steering_writer))

    def pump(self):
        now = time.monotonic()
        if not self.running or now < self.next:
            return
        self.next = now + self.PERIOD
        header = Header(stamp_now(), "map")
        self.velocity_writer.write(VelocityFactorArray(header, list(self.velocity)))
        self.steering_writer.write(SteeringFactorArray(header, list(self.steering)))


class World:
    def __init__(self, domain, velocity_input, steering_input):
        self.planners = {
            name: Planner(domain, name, interfaces, locks)
            for name, (interfaces, locks) in PLANNERS.items()
        }
        self.interfaces = {
            name: interface
            for planner in self.planners.values()
            for name, interface in planner.interfaces.items()
        }
        self.operator = Operator(self, domain)
        self.adapi = DefaultAdapi(domain, velocity_input, steering_input)
        self.pumping = False

    def pump(self):
        if self.pumping:
            return
        self.pumping = True
        try:
            for planner in self.planners.values():
                planner.pump()
            self.adapi.pump()
            self.operator.velocity.poll()
            self.operator.steering.poll()
        finally:
            self.pumping = False

    def wait(self, predicate, timeout):
        """Pumps until `predicate()` holds (True) or `timeout` s passed (False)."""
        deadline = time.monotonic() + bounded(timeout)
        while True:
            self.pump()
            if predicate():
                return True
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.002)

    def settle(self, seconds):
        self.wait(lambda: False, seconds)

    def unmatched(self):
        missing = [f"{name}'s endpoints" for name, i in self.interfaces.items() if not i.matched()]
        if not self.adapi.matched():
            missing.append("default_adapi's factor writers")
        for client in self.operator.clients:
            missing += client.unmatched()
        for stream in (self.operator.velocity, self.operator.steering):
            if stream.reader.get_subscription_matched_status().current_count == 0:
                missing.append(f"reader of {stream.topic}")
        return missing

    # ---- the operator's calls

    def command(self, scene, decision):
        return self.operator.set_commands.call(
            [CooperationCommand(UUID(scene), CooperationDecision(decision))])

    def policy(self, behavior, policy, sequences=("",)):
        return self.operator.set_policies.call(
            [CooperationPolicy(behavior, sequence, policy) for sequence in sequences])

    def policies(self):
        reply = self.operator.get_policies.call(0)
        if reply is None:
            return None
        return {(p.behavior, p.sequence): p.policy for p in reply.policies}

    # ---- what the AD API shows

    def shown(self, interface, scene):
        """The newest factor's cooperation status of `scene`, or None if not shown."""
        stream = self.operator.steering if BEHAVIOR[interface][1] else self.operator.velocity
        message = stream.newest()
        if message is None:
            return None
        for factor in message.factors:
            if factor.cooperation and bytes(factor.cooperation[0].uuid.uuid) == scene:
                return factor.cooperation[0]
        return None

    def merged(self, interface, scene, policies):
        """The merged decision the AD API shows for `scene` (True: activate), from its
        cooperation status and its module's policy; None if it is not shown."""
        status = self.shown(interface, scene)
        if status is None:
            return None
        cooperator = status.cooperator.decision
        if cooperator in (ACTIVATE, DEACTIVATE):
            return cooperator == ACTIVATE
        behavior = BEHAVIOR[interface][0]
        policy = next((p for (b, _), p in policies.items() if b == behavior), OPTIONAL)
        if cooperator == AUTONOMOUS or policy == OPTIONAL:
            return status.autonomous.decision == ACTIVATE
        return False


__all__ = ["World", "LEFT", "steering_factor", "velocity_factor", "ACTIVATE", "AUTONOMOUS",
           "DEACTIVATE", "UNDECIDED", "OPTIONAL", "REQUIRED"]
