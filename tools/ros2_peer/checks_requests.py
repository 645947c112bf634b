"""The checks of the requests that change the node or that it refuses: the operator's commands
and policies, a scene waiting for the operator through to its removal, the sync requests it
refuses, malformed requests, many calls in a row, and new clients calling at once.
"""

import time

from .checks_start import refresh
from .dds import (
    CONFIGURED,
    GET_POLICIES,
    PUBLICATION_TIMEOUT,
    STEERING,
    VELOCITY,
    new_uuid,
    report,
)
from .matching import (
    Any,
    Contains,
    NonEmpty,
    RecentStamp,
    StartsWith,
    cooperation,
    diff,
    factor_of,
    factor_uuids,
    factors_problems,
    no_reply,
    node_status,
    policies_of,
    refusal,
    status_problems,
    steering_factor,
    sync_answer,
    sync_problems,
    velocity_factor,
)
from .messages import (
    GetPoliciesCall,
    GetPoliciesReply,
    ACTIVATE,
    DEACTIVATE,
    LEFT,
    MODULE_INTERSECTION,
    MODULE_LANE_CHANGE_LEFT,
    NO_EFFECT,
    PARAMETER_ERROR,
    REQUIRED,
    RIGHT,
    RTC_ACTIVATE,
    RTC_DEACTIVATE,
    RUNNING,
    SUCCESS,
    UNDECIDED,
    UNKNOWN,
    WAITING,
    Activation,
    Command,
    CooperateStatusArray,
    CooperateStatusByteSafe,
    CooperationCommand,
    CooperationDecision,
    CooperationPolicy,
    GetCooperationPoliciesResponse,
    Header,
    Module,
    PolicyWithoutNul,
    ResponseStatus,
    State,
    SteeringFactorArray,
    SyncCooperateStatusResponse,
    SyncResult,
    Time,
    UUID,
    VelocityFactorArray,
)


def check_set_commands(peer, checks, s):
    client = peer.set_commands

    def command(scene, decision):
        return CooperationCommand(UUID(scene), CooperationDecision(decision))

    def deactivate():
        return status_problems(client.call([command(s.turn, DEACTIVATE)]), SUCCESS, client)

    checks.run("set_commands: DEACTIVATE a lane change scene is accepted", deactivate)
    after = time.monotonic()
    checks.run(
        f"{STEERING}: the lane change's cooperator decision shows DEACTIVATE",
        lambda: factors_problems(peer.steering, SteeringFactorArray(
            Header(RecentStamp(), "map"),
            [steering_factor(s.back, 5.0, 30.0, RIGHT, "avoidance", "return", ACTIVATE,
                             UNDECIDED),
             steering_factor(s.turn, 10.5, 50.75, LEFT, "lane-change", "", DEACTIVATE,
                             DEACTIVATE)]),
            [s.back, s.turn], after=after))

    def force_deactivated():
        # The module now says go, and the scene runs: the operator's DEACTIVATE overrules it.
        s.turn_reported = (True, RUNNING, 9.5, 49.75)
        reply = peer.sync.call("lane_change_left", [report(s.turn, *s.turn_reported)], [], [])
        return sync_problems(reply, sync_answer(
            [(s.turn, True, "")],
            [node_status(s.turn, MODULE_LANE_CHANGE_LEFT, True, RUNNING, 9.5, 49.75,
                         RTC_DEACTIVATE, False)],
            [Activation(UUID(s.turn), False, False, True)]), peer.sync)

    checks.run("sync lane_change_left: the operator's DEACTIVATE reaches the module as "
               "force-deactivated", force_deactivated)

    refusals = [
        ("an unknown scene", [command(s.stray, ACTIVATE)], refusal("unknown scene")),
        ("an undefined decision (7)", [command(s.stop, 7)], ResponseStatus(
            False, PARAMETER_ERROR,
            "commands[0].cooperator.decision: 7 is not a CooperationDecision constant")),
        ("decision UNKNOWN (0)", [command(s.stop, UNKNOWN)], refusal("UNKNOWN")),
        ("the same scene twice", [command(s.stop, ACTIVATE), command(s.stop, ACTIVATE)],
         refusal("twice")),
        ("a valid command beside an unknown scene",
         [command(s.stop, ACTIVATE), command(s.stray, ACTIVATE)], refusal("unknown scene")),
    ]
    for what, commands, expected in refusals:
        checks.run(f"set_commands refused: {what}",
                   lambda commands=commands, expected=expected:
                   status_problems(client.call(commands), expected, client))

    checks.run("set_commands: an empty batch succeeds with NO_EFFECT",
               lambda: status_problems(client.call([]),
                                       ResponseStatus(True, NO_EFFECT, "the batch is empty"),
                                       client))

    def unchanged():
        message = peer.velocity.next()
        if message is None:
            return [f"no publication on {VELOCITY}"]
        factor = factor_of(message, s.stop)
        if factor is None:
            return ["the intersection scene is not listed"]
        return diff(cooperation(s.stop, ACTIVATE, UNDECIDED), factor.cooperation,
                    "intersection.cooperation")

    checks.run("set_commands: the refused commands changed nothing", unchanged)


def check_policies(peer, checks, s):
    refresh(peer, s)
    client = peer.set_policies

    def policy(behavior, value, sequence_=""):
        return CooperationPolicy(behavior, sequence_, value)

    def get():
        reply = peer.get_policies.call(0)
        if reply is None or not reply.status.success:
            raise AssertionError(f"get_policies answered {reply!r}")
        return policies_of(reply)

    before = {}

    def required():
        before.update(get())
        return status_problems(client.call([policy("intersection", REQUIRED)]), SUCCESS, client)

    checks.run("set_policies: intersection required is accepted", required)

    def shown():
        after = get()
        wanted = {**before, ("intersection", ""): REQUIRED}
        return [] if after == wanted else [
            f"{ {k: v for k, v in after.items() if wanted.get(k) != v} } differ from {wanted}"]

    checks.run("get_policies: shows intersection required, every other module unchanged", shown)

    def holds():
        reply = peer.sync.call("intersection", [report(s.stop, True, RUNNING, 35.25, 35.25)],
                               [], [])
        return sync_problems(reply, sync_answer(
            [(s.stop, True, "")],
            [node_status(s.stop, MODULE_INTERSECTION, True, RUNNING, 35.25, 35.25,
                         RTC_DEACTIVATE, False)],
            [Activation(UUID(s.stop), False, False, False)]), peer.sync)

    checks.run("sync intersection: the required policy holds the safe scene for the operator",
               holds)

    refusals = [
        ("a module no configuration names", [policy("lane-chnage", REQUIRED)],
         refusal("lane-chnage")),
        ("a behaviour that is no name", [policy("lane_change", REQUIRED)],
         refusal("policies[0].behavior")),
        ("an undefined policy (9)", [policy("lane-change", 9)], refusal("policies[0].policy")),
        ("a valid setting beside an unknown module",
         [policy("crosswalk", REQUIRED), policy("lane-chnage", REQUIRED)],
         refusal("lane-chnage")),
    ]
    for what, policies, expected in refusals:
        checks.run(f"set_policies refused: {what}",
                   lambda policies=policies, expected=expected:
                   status_problems(client.call(policies), expected, client))

    def unchanged():
        after = get()
        wanted = {**before, ("intersection", ""): REQUIRED}
        return [] if after == wanted else [f"policies now {after}, expected {wanted}"]

    checks.run("set_policies: the refusals changed no policy", unchanged)
    checks.run("set_policies: an empty batch succeeds with NO_EFFECT",
               lambda: status_problems(client.call([]),
                                       ResponseStatus(True, NO_EFFECT, "the batch is empty"),
                                       client))


def check_operator_round_trip(peer, checks, s):
    """A scene waiting for the operator, the operator's ACTIVATE, the module learning it, and
    the scene's removal (intersection's policy is required by now)."""
    refresh(peer, s)
    sync = peer.sync
    stop_status = report(s.stop, True, RUNNING, 35.25, 35.25)

    def awaits():
        reply = sync.call("intersection", [stop_status, report(s.held, False, RUNNING, 20.0, 20.0)],
                          [], [])
        return sync_problems(reply, sync_answer(
            [(s.stop, True, ""), (s.held, True, "")],
            [node_status(s.stop, MODULE_INTERSECTION, True, RUNNING, 35.25, 35.25,
                         RTC_DEACTIVATE, False),
             node_status(s.held, MODULE_INTERSECTION, False, RUNNING, 20.0, 20.0,
                         RTC_DEACTIVATE, False)],
            [Activation(UUID(s.stop), False, False, False),
             Activation(UUID(s.held), False, False, False)]), sync)

    checks.run("sync intersection: an unsafe scene under a required policy waits, not activated",
               awaits)

    def listed(cooperator):
        return VelocityFactorArray(
            Header(RecentStamp(), "map"),
            [velocity_factor(s.walk, 12.5, "crosswalk", DEACTIVATE, UNDECIDED),
             velocity_factor(s.held, 20.0, "intersection", DEACTIVATE, cooperator),
             velocity_factor(s.stop, 35.25, "intersection", ACTIVATE, UNDECIDED)])

    checks.run(f"{VELOCITY}: the waiting scene is listed, nearest first, cooperator UNDECIDED",
               lambda: factors_problems(peer.velocity, listed(UNDECIDED),
                                        [s.walk, s.held, s.stop]))

    checks.run("set_commands: the operator ACTIVATEs the waiting scene",
               lambda: status_problems(peer.set_commands.call(
                   [CooperationCommand(UUID(s.held), CooperationDecision(ACTIVATE))]),
                   SUCCESS, peer.set_commands))
    answered = time.monotonic()

    def shown():
        wanted = {s.walk, s.held, s.stop}

        def activated(message):
            factor = factor_of(message, s.held)
            return set(factor_uuids(message)) == wanted and factor is not None and \
                factor.cooperation[0].cooperator.decision == ACTIVATE

        if peer.velocity.wait(activated, PUBLICATION_TIMEOUT) is None:
            return [f"no publication showed the ACTIVATE within {PUBLICATION_TIMEOUT} s"]
        # The node publishes a changed state before it answers: from shortly after the answer
        # on (delivery through two writers is not ordered), every publication shows it.
        settle = answered + 0.2
        later = peer.velocity.wait(lambda _: True, PUBLICATION_TIMEOUT, after=settle)
        if later is None:
            return ["no publication after the answer"]
        return diff(listed(ACTIVATE), later, VELOCITY)

    checks.run(f"{VELOCITY}: the publications after the answer show cooperator ACTIVATE",
               shown)

    def learns():
        reply = sync.call("intersection", [stop_status, report(s.held, False, RUNNING, 19.5, 19.5)],
                          [], [])
        return sync_problems(reply, sync_answer(
            [(s.stop, True, ""), (s.held, True, "")],
            [node_status(s.stop, MODULE_INTERSECTION, True, RUNNING, 35.25, 35.25,
                         RTC_DEACTIVATE, False),
             node_status(s.held, MODULE_INTERSECTION, False, RUNNING, 19.5, 19.5,
                         RTC_ACTIVATE, False)],
            [Activation(UUID(s.stop), False, False, False),
             Activation(UUID(s.held), True, True, False)]), sync)

    checks.run("sync intersection: the module learns activated and force-activated", learns)

    def removed():
        reply = sync.call("intersection", [], [], [UUID(s.held)])
        return sync_problems(reply, sync_answer(
            [(s.held, True, "")],
            [node_status(s.stop, MODULE_INTERSECTION, True, RUNNING, 35.25, 35.25,
                         RTC_DEACTIVATE, False)],
            [Activation(UUID(s.stop), False, False, False)]), sync)

    checks.run("sync intersection: the module removes the scene", removed)
    checks.run(
        f"{VELOCITY}: the removed scene is no longer listed",
        lambda: factors_problems(peer.velocity, VelocityFactorArray(
            Header(RecentStamp(), "map"),
            [velocity_factor(s.walk, 12.5, "crosswalk", DEACTIVATE, UNDECIDED),
             velocity_factor(s.stop, 35.25, "intersection", ACTIVATE, UNDECIDED)]),
            [s.walk, s.stop]))
    checks.run("set_commands refused: a removed scene",
               lambda: status_problems(peer.set_commands.call(
                   [CooperationCommand(UUID(s.held), CooperationDecision(DEACTIVATE))]),
                   refusal("retired"), peer.set_commands))

    def revived():
        reply = sync.call("intersection", [report(s.held, False, RUNNING, 18.0, 18.0)], [], [])
        if reply is None:
            return [no_reply(sync)]
        problems = diff(False, reply.success, "response.success")
        problems += diff([SyncResult(UUID(s.held), False, NonEmpty())], reply.results,
                         "response.results")
        if any(bytes(a.uuid.uuid) == s.held for a in reply.activations):
            problems.append("the removed scene is among the activations")
        return problems

    checks.run("sync intersection: a removed scene cannot be reported again", revived)


def check_sync_refusals(peer, checks, s):
    refresh(peer, s)
    sync = peer.sync

    def unknown_interface():
        reply = sync.call("dynamic_obstacle_avoidance", [report(s.stray, True, WAITING, 1.0, 1.0)],
                          [], [])
        if reply is None:
            return [no_reply(sync)]
        return diff(SyncCooperateStatusResponse(
            False, Contains("dynamic_obstacle_avoidance"), [], CooperateStatusArray(Any(), []), []),
            reply, "response")

    checks.run("sync refused: an unknown interface, as a whole", unknown_interface)

    def unstated():
        reply = sync.call("static_obstacle_avoidance_right",
                          [report(s.stray, True, WAITING, 1.0, 2.0)], [], [])
        if reply is None:
            return [no_reply(sync)]
        problems = diff(False, reply.success, "response.success")
        problems += diff([SyncResult(UUID(s.stray), False, Contains("state its sequence"))],
                         reply.results, "response.results")
        return problems

    checks.run("sync refused: a new avoidance scene without its sequence", unstated)

    def foreign():
        reply = sync.call("lane_change_right", [report(s.turn, True, RUNNING, 9.0, 49.0)], [], [])
        if reply is None:
            return [no_reply(sync)]
        problems = diff(False, reply.success, "response.success")
        problems += diff([SyncResult(UUID(s.turn), False, Contains("lane_change_left"))],
                         reply.results, "response.results")
        return problems

    checks.run("sync refused: another interface's scene", foreign)


def check_malformed(peer, checks):
    cdr = StartsWith("CDR at byte")
    refused = ResponseStatus(False, PARAMETER_ERROR, cdr)
    checks.run("set_commands malformed (a count of 1, no command): answered, CDR at byte …",
               lambda: status_problems(peer.set_commands.call(1, writer="short"), refused,
                                       peer.set_commands))
    checks.run("set_policies malformed (a string without its NUL): answered, CDR at byte …",
               lambda: status_problems(peer.set_policies.call(
                   [PolicyWithoutNul(list(b"lane-change"), "", REQUIRED)], writer="no NUL"),
                   refused, peer.set_policies))

    def long_get():
        reply = peer.get_policies.call(0, 0x0102030405060708, writer="long")
        if reply is None:
            return [no_reply(peer.get_policies)]
        return diff(GetCooperationPoliciesResponse(refused, []), reply, "response")

    checks.run("get_policies malformed (15 bytes after the message): answered, CDR at byte …",
               long_get)

    def bad_boolean():
        status = CooperateStatusByteSafe(Time(0, 0), UUID(new_uuid()), Module(0), 2, False,
                                         Command(0), State(WAITING), False, 1.0, 1.0)
        reply = peer.sync.call("crosswalk", [status], [], [], writer="boolean 2")
        if reply is None:
            return [no_reply(peer.sync)]
        return diff(SyncCooperateStatusResponse(
            False, cdr, [], CooperateStatusArray(Any(), []), []), reply, "response")

    checks.run("sync malformed (a boolean 2): answered, CDR at byte …", bad_boolean)
    checks.run("get_policies: the node answers after the malformed requests",
               lambda: status_problems(peer.get_policies.call(0), SUCCESS, peer.get_policies))


# How many malformed requests, and how many syncs over max_batch, the flood sends;
# tools/ros2-interop counts them in the node's log.
FLOOD = 300
SYNC_FLOOD = 20
# The built-in settings' max_batch (adapters/config/cooperation.param.yaml).
MAX_BATCH = 1024


def check_malformed_flood(peer, checks, count=FLOOD):
    """Malformed requests in a row, each answered with its refusal: the node logs the first of a
    period whole and counts the others (tools/ros2-interop reads its log)."""
    def flood():
        client = peer.get_policies
        unanswered, wrong = 0, 0
        for _ in range(count):
            reply = client.call(0, 0x0102030405060708, writer="long")
            if reply is None:
                unanswered += 1
            elif reply.status.success or not reply.status.message.startswith("CDR at byte"):
                wrong += 1
        counted = ((unanswered, "unanswered"), (wrong, "not refused as malformed"))
        return [f"{n} of {count} {what}" for n, what in counted if n]

    checks.run(f"get_policies malformed, {count} in a row: each refused", flood)

    def too_long():
        removed = [UUID(new_uuid()) for _ in range(MAX_BATCH + 1)]
        unanswered, wrong = 0, 0
        for _ in range(SYNC_FLOOD):
            reply = peer.sync.call("crosswalk", [], [], removed)
            if reply is None:
                unanswered += 1
            elif reply.success or "max_batch" not in reply.message:
                wrong += 1
        counted = ((unanswered, "unanswered"), (wrong, "not refused for max_batch"))
        return [f"{n} of {SYNC_FLOOD} {what}" for n, what in counted if n]

    checks.run(f"sync of {MAX_BATCH + 1} removals, {SYNC_FLOOD} in a row: each refused", too_long)


def check_many_calls(peer, checks, count=100):
    def many():
        client = peer.get_policies
        strays = len(client.strays)
        lost, refused, latencies = 0, 0, []
        for _ in range(count):
            began = time.monotonic()
            reply = client.call(0)
            if reply is None:
                lost += 1
            else:
                latencies.append(time.monotonic() - began)
                if not reply.status.success or len(reply.policies) != len(CONFIGURED):
                    refused += 1
        problems = []
        if lost:
            problems.append(f"{lost} of {count} calls unanswered (the last: {client.unanswered})")
        if refused:
            problems.append(f"{refused} replies not a full success")
        if len(client.strays) > strays:
            problems.append(f"{len(client.strays) - strays} replies matched no call")
        if latencies:
            latencies.sort()
            print(f"  {count} get_policies calls: median {latencies[len(latencies) // 2] * 1e3:.1f}"
                  f" ms, slowest {latencies[-1] * 1e3:.1f} ms", flush=True)
        return problems

    checks.run(f"get_policies: {count} calls in a row, no reply lost", many)


def check_fresh_clients(peer, checks, count=10):
    """Clients whose reply reader appears only just after their call: the node must hold each
    reply until it has matched the reader (up to 100 ms, as rmw_cyclonedds_cpp does), or the
    reply is lost, since a volatile writer sends nothing to a reader it matches later. A client
    made just before its first call races the same way, less often."""

    def fresh():
        from cyclonedds.domain import DomainParticipant
        from cyclonedds.pub import DataWriter
        from cyclonedds.sub import DataReader
        from cyclonedds.topic import Topic

        lost = 0
        for index in range(count):
            participant = DomainParticipant(peer.domain)
            requests = Topic(participant, f"rq{GET_POLICIES}Request", GetPoliciesCall)
            writer = DataWriter(participant, requests, peer.service_qos)
            deadline = time.monotonic() + 5
            while (writer.get_publication_matched_status().current_count == 0
                   and time.monotonic() < deadline):
                time.sleep(0.001)
            guid = (index + 1) << 32 | 7
            writer.write(GetPoliciesCall(guid, 1, 0))
            replies = Topic(participant, f"rr{GET_POLICIES}Reply", GetPoliciesReply)
            reader = DataReader(participant, replies, peer.service_qos)
            reply = None
            deadline = time.monotonic() + 2
            while reply is None and time.monotonic() < deadline:
                for sample in reader.take(N=10):
                    if isinstance(sample, GetPoliciesReply) and (sample.guid, sample.seq) == (guid, 1):
                        reply = sample
                time.sleep(0.001)
            if reply is None:
                lost += 1
            del reader, writer, participant
        return [f"{lost} of {count} replies lost"] if lost else []

    checks.run(f"get_policies: {count} clients whose reply reader appears just after the call, "
               "no reply lost", fresh)
