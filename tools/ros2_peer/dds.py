"""The DDS side of the peer: the node's service and topic names, the run's time budget, and the
participant with its readers (`Stream`) and its service clients (`Client`) as
`rmw_cyclonedds_cpp` makes them.
"""

import random
import time
import uuid as uuidlib

from .messages import (
    Command,
    CooperateStatus,
    GetPoliciesCall,
    GetPoliciesCallLong,
    GetPoliciesReply,
    Module,
    ParticipantEntitiesInfo16,
    ParticipantEntitiesInfo24,
    SetCommandsCall,
    SetCommandsCallShort,
    SetCommandsReply,
    SetPoliciesCall,
    SetPoliciesCallNoNul,
    SetPoliciesReply,
    State,
    SteeringFactorArray,
    SyncCall,
    SyncCallBadBoolean,
    SyncReply,
    Time,
    UUID,
    VelocityFactorArray,
)

# ---- the node's names, and the run's timing

# config/cooperation.param.yaml: every standard module, each optional.
CONFIGURED = {
    ("avoidance", "change"), ("avoidance", "return"), ("crosswalk", ""), ("goal-planner", ""),
    ("intersection", ""), ("lane-change", ""), ("no-stopping-area", ""), ("rear-check", ""),
    ("roundabout", ""), ("start-planner", ""), ("traffic-signal", ""),
    ("user-defined-attention-area", ""), ("virtual-traffic-light", ""),
}

SET_COMMANDS = "/api/planning/cooperation/set_commands"
SET_POLICIES = "/api/planning/cooperation/set_policies"
GET_POLICIES = "/api/planning/cooperation/get_policies"
SYNC = "/cooperation/rtc/sync"
VELOCITY = "rt/api/planning/velocity_factors"
STEERING = "rt/api/planning/steering_factors"
DISCOVERY_INFO = "ros_discovery_info"

# How long one service call waits for its reply, in seconds.
CALL_TIMEOUT = 2.0
# How long the node's endpoints are waited for at the start.
DISCOVERY_TIMEOUT = 15.0
# How long a publication showing a change is waited for.
PUBLICATION_TIMEOUT = 1.5
# The whole run's budget: past it, every wait ends at once, so the peer never hangs.
BUDGET = 80.0

STARTED = time.monotonic()


def budget_left():
    return max(0.0, STARTED + BUDGET - time.monotonic())


def bounded(timeout):
    return min(timeout, budget_left())


# ---- DDS


def new_uuid():
    return uuidlib.uuid4().bytes


def uuid_text(raw):
    return str(uuidlib.UUID(bytes=bytes(raw)))


def report(scene, safe, state, start, finish, requested=False):
    """A status as a planning module reports it; the fields the node fills are left zero."""
    return CooperateStatus(
        Time(0, 0), UUID(scene), Module(0), safe, requested, Command(0), State(state), False,
        start, finish,
    )


class Peer:
    """The participant, its readers, and its service clients."""

    def __init__(self, domain, distro):
        from cyclonedds.builtin import (
            BuiltinDataReader,
            BuiltinTopicDcpsParticipant,
            BuiltinTopicDcpsPublication,
            BuiltinTopicDcpsSubscription,
        )
        from cyclonedds.core import Policy, Qos
        from cyclonedds.domain import DomainParticipant
        from cyclonedds.util import duration

        self.domain = domain
        self.participant = DomainParticipant(domain)
        reliable = Policy.Reliability.Reliable(duration(seconds=1))
        # The node's service QoS: RELIABLE, VOLATILE, KEEP_LAST 10.
        self.service_qos = Qos(reliable, Policy.Durability.Volatile, Policy.History.KeepLast(10))
        # The factors are published RELIABLE, VOLATILE, KEEP_LAST 1; this reader keeps more,
        # so that nothing is lost between two polls.
        stream_qos = Qos(reliable, Policy.Durability.Volatile, Policy.History.KeepLast(100))
        graph_qos = Qos(reliable, Policy.Durability.TransientLocal, Policy.History.KeepLast(10))
        self.gid_len = 16 if distro == "jazzy" else 24
        info = ParticipantEntitiesInfo16 if self.gid_len == 16 else ParticipantEntitiesInfo24

        self.velocity = Stream(self, VELOCITY, VelocityFactorArray, stream_qos)
        self.steering = Stream(self, STEERING, SteeringFactorArray, stream_qos)
        self.graph = Stream(self, DISCOVERY_INFO, info, graph_qos)
        self.streams = [self.velocity, self.steering, self.graph]

        self.set_commands = Client(self, SET_COMMANDS, SetCommandsCall, SetCommandsReply)
        self.set_policies = Client(self, SET_POLICIES, SetPoliciesCall, SetPoliciesReply)
        self.get_policies = Client(self, GET_POLICIES, GetPoliciesCall, GetPoliciesReply)
        self.sync = Client(self, SYNC, SyncCall, SyncReply)
        self.clients = [self.set_commands, self.set_policies, self.get_policies, self.sync]
        self.set_commands.add_writer("short", SetCommandsCallShort)
        self.set_policies.add_writer("no NUL", SetPoliciesCallNoNul)
        self.get_policies.add_writer("long", GetPoliciesCallLong)
        self.sync.add_writer("boolean 2", SyncCallBadBoolean)

        self.builtin_participants = BuiltinDataReader(self.participant, BuiltinTopicDcpsParticipant)
        self.builtin_publications = BuiltinDataReader(self.participant, BuiltinTopicDcpsPublication)
        self.builtin_subscriptions = BuiltinDataReader(
            self.participant, BuiltinTopicDcpsSubscription)
        self.participants, self.publications, self.subscriptions = {}, {}, {}

    def pump(self):
        for stream in self.streams:
            stream.poll()

    def discovered(self):
        """The participants and endpoints discovered so far, by GUID."""
        for reader, into in ((self.builtin_participants, self.participants),
                             (self.builtin_publications, self.publications),
                             (self.builtin_subscriptions, self.subscriptions)):
            for sample in reader.take(N=500):
                if hasattr(sample, "key"):
                    into[sample.key.bytes] = sample
        return self.participants, self.publications, self.subscriptions

    def unmatched(self):
        """The endpoints that have not matched the node's yet."""
        missing = []
        for client in self.clients:
            missing += client.unmatched()
        for stream in self.streams:
            if stream.reader.get_subscription_matched_status().current_count == 0:
                missing.append(f"reader of {stream.topic}")
        return missing

    def wait_matched(self, timeout):
        deadline = time.monotonic() + bounded(timeout)
        while True:
            self.pump()
            missing = self.unmatched()
            if not missing or time.monotonic() >= deadline:
                return missing
            time.sleep(0.02)


class Stream:
    """A topic's reader with every sample it received and when."""

    def __init__(self, peer, topic, data_type, qos):
        from cyclonedds.sub import DataReader
        from cyclonedds.topic import Topic

        self.peer = peer
        self.topic = topic
        self.data_type = data_type
        self.reader = DataReader(peer.participant, Topic(peer.participant, topic, data_type), qos)
        self.samples = []  # (time.monotonic() when taken, sample)
        self.errors = []

    def poll(self):
        try:
            taken = self.reader.take(N=100)
        except Exception as error:  # noqa: BLE001
            self.errors.append(f"{type(error).__name__}: {error}")
            return
        now = time.monotonic()
        for sample in taken:
            if isinstance(sample, self.data_type):
                self.samples.append((now, sample))

    def newest(self):
        self.peer.pump()
        return self.samples[-1][1] if self.samples else None

    def wait(self, predicate, timeout=PUBLICATION_TIMEOUT, after=None):
        """The first sample taken after `after` (monotonic time; default: any) for which
        `predicate` holds, waiting at most `timeout` s; None if none came."""
        deadline = time.monotonic() + bounded(timeout)
        seen = 0
        while True:
            self.peer.pump()
            for taken, sample in self.samples[seen:]:
                if (after is None or taken > after) and predicate(sample):
                    return sample
            seen = len(self.samples)
            if time.monotonic() >= deadline:
                return None
            time.sleep(0.005)

    def next(self, timeout=PUBLICATION_TIMEOUT):
        """The first sample taken from now on."""
        return self.wait(lambda _: True, timeout, after=time.monotonic())


class Client:
    """A service client as rmw_cyclonedds_cpp makes one: a request writer on
    `rq<service>Request`, a reply reader on `rr<service>Reply`, its own guid and increasing
    sequence numbers; a reply is its call's when both match."""

    def __init__(self, peer, service, call_type, reply_type):
        from cyclonedds.pub import DataWriter
        from cyclonedds.sub import DataReader
        from cyclonedds.topic import Topic

        self.peer = peer
        self.service = service
        self.call_type = call_type
        self.reply_type = reply_type
        self.request_topic = f"rq{service}Request"
        self.reply_topic = f"rr{service}Reply"
        dp = peer.participant
        self.writers = {None: DataWriter(dp, Topic(dp, self.request_topic, call_type),
                                         peer.service_qos)}
        self.reader = DataReader(dp, Topic(dp, self.reply_topic, reply_type), peer.service_qos)
        self.guid = random.getrandbits(63) | 1
        self.seq = 0
        self.strays = []  # replies to no call of this client
        self.unanswered = ""  # why the last call got no reply

    def add_writer(self, name, call_type):
        """Another request writer on the same topic, with a type of the same name whose body
        differs: for malformed requests."""
        from cyclonedds.pub import DataWriter
        from cyclonedds.topic import Topic

        dp = self.peer.participant
        self.writers[name] = DataWriter(dp, Topic(dp, self.request_topic, call_type),
                                        self.peer.service_qos)

    def unmatched(self):
        missing = []
        for name, writer in self.writers.items():
            if writer.get_publication_matched_status().current_count == 0:
                kind = f"{name} request writer" if name else "request writer"
                missing.append(f"{kind} of {self.service}")
        if self.reader.get_subscription_matched_status().current_count == 0:
            missing.append(f"reply reader of {self.service}")
        return missing

    def matched(self, writer=None):
        return (self.writers[writer].get_publication_matched_status().current_count > 0
                and self.reader.get_subscription_matched_status().current_count > 0)

    def call(self, *fields, timeout=CALL_TIMEOUT, writer=None):
        """Writes a request with these fields after the header and waits for its reply: the
        reply, or None after `timeout` s, or at once if the node's endpoints never matched."""
        self.seq += 1
        seq = self.seq
        chosen = self.writers[writer]
        if not self.matched(writer):
            self.unanswered = "the node's request reader or reply writer is not matched"
            return None
        self.unanswered = f"no reply within {timeout} s"
        chosen.write(chosen.data_type(self.guid, seq, *fields))
        deadline = time.monotonic() + bounded(timeout)
        while True:
            for reply in self.reader.take(N=50):
                if not isinstance(reply, self.reply_type):
                    continue
                if reply.guid == self.guid and reply.seq == seq:
                    return reply
                self.strays.append((reply.guid, reply.seq))
            if time.monotonic() >= deadline:
                return None
            self.peer.pump()
            time.sleep(0.001)
