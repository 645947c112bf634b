"""The ROS 2 side of `tools/ros2-interop`: a Cyclone DDS participant (`cyclonedds` from PyPI,
the version of `tools/cdr-requirements.txt`) that talks to `cooperation-dds` as ROS 2 nodes
on `rmw_cyclonedds_cpp` do, and checks every answer and publication.

It is at once an operator (the AD API cooperation services and the two factor topics), a
planning module (`/cooperation/rtc/sync`) and a ROS graph tool (`ros_discovery_info`). The
message types are those of `tools/cdr_golden.py`, which `adapters/tests/cdr.rs` holds the node's
encoder to; the sync service's types and the request/reply wrappers are declared in
`messages.py`.

Each check prints one line, `PASS name` or `FAIL name: why`, and the run ends with
`ros2 interop peer: N passed, M failed`; the exit status is 1 if any check failed. Every wait
is bounded. With `--self-test` it checks only its own wrapper types' bytes, with no node.

    target/cdr-venv/bin/python tools/ros2_peer --domain 42 [--distro humble|jazzy]
"""

import argparse
import dataclasses
import sys
from pathlib import Path

# Import this package's modules, and the message types of tools/cdr_golden.py, from tools/
# without leaving compiled files in the tree. Run as `python tools/ros2_peer`, the package's own
# folder is first on the path: it is taken off, so that its modules are imported only as the
# package's. (Before this runs, Python imports standard modules with that folder first on the
# path already: no module here may be named as one of them, as a `types.py` would be.)
sys.dont_write_bytecode = True
HERE = Path(__file__).resolve().parent
sys.path[:] = [entry for entry in sys.path if Path(entry or ".").resolve() != HERE]
sys.path.insert(0, str(HERE.parent))

from ros2_peer.checks_requests import (  # noqa: E402
    check_fresh_clients,
    check_malformed,
    check_malformed_flood,
    check_many_calls,
    check_operator_round_trip,
    check_policies,
    check_set_commands,
    check_sync_refusals,
)
from ros2_peer.checks_one_core import check_one_core  # noqa: E402
from ros2_peer.checks_start import (  # noqa: E402
    Scenes,
    check_get_policies,
    check_graph,
    check_scenes_reported,
    check_streams_at_start,
)
from ros2_peer.dds import BUDGET, DISCOVERY_TIMEOUT, Peer, budget_left  # noqa: E402
from ros2_peer.matching import Checks, diff  # noqa: E402
from ros2_peer.messages import (  # noqa: E402
    SUCCESS,
    Activation,
    Command,
    CooperateStatus,
    CooperateStatusArray,
    CooperateStatusByteSafe,
    CooperationCommand,
    CooperationDecision,
    CooperationPolicy,
    GetCooperationPoliciesRequest,
    GetCooperationPoliciesResponse,
    GetPoliciesCall,
    GetPoliciesCallLong,
    GetPoliciesReply,
    Module,
    PolicyWithoutNul,
    ResponseStatus,
    SetCommandsCall,
    SetCommandsCallShort,
    SetCommandsReply,
    SetCooperationCommandsRequest,
    SetCooperationCommandsResponse,
    SetCooperationPoliciesRequest,
    SetCooperationPoliciesResponse,
    SetPoliciesCall,
    SetPoliciesCallNoNul,
    SetPoliciesReply,
    State,
    StatedSequence,
    SyncCall,
    SyncCallBadBoolean,
    SyncCooperateStatusRequest,
    SyncCooperateStatusResponse,
    SyncReply,
    SyncResult,
    Time,
    UUID,
)


def interop(domain, distro):
    checks = Checks()
    peer = Peer(domain, distro)

    missing = peer.wait_matched(DISCOVERY_TIMEOUT)
    checks.record(
        f"discovery: every service and topic matched the node's within {DISCOVERY_TIMEOUT:.0f} s",
        [f"not matched: {', '.join(missing)}"] if missing else [])
    endpoints = sum(len(client.writers) + 1 for client in peer.clients) + len(peer.streams)
    if len(missing) == endpoints:
        print("  nothing of the node was discovered: no further checks", flush=True)
        return checks

    check_graph(peer, checks)
    check_streams_at_start(peer, checks)
    check_get_policies(peer, checks)
    scenes = Scenes()
    check_scenes_reported(peer, checks, scenes)
    check_set_commands(peer, checks, scenes)
    check_policies(peer, checks, scenes)
    check_operator_round_trip(peer, checks, scenes)
    check_sync_refusals(peer, checks, scenes)
    check_malformed(peer, checks)
    check_malformed_flood(peer, checks)
    check_many_calls(peer, checks)
    check_fresh_clients(peer, checks)

    for stream in peer.streams:
        checks.run(f"{stream.topic}: every sample decoded",
                   lambda stream=stream: [f"{len(stream.errors)} reads failed: "
                                          f"{stream.errors[-1]}"] if stream.errors else [])
    if budget_left() <= 0:
        checks.record("the run ended within its budget", f"over {BUDGET:.0f} s")
    return checks


def one_core(domain, address):
    """`cooperation-server --dds-domain`: its DDS door and its rosbridge door on one core."""
    checks = Checks()
    peer = Peer(domain, "humble")
    missing = peer.wait_matched(DISCOVERY_TIMEOUT)
    checks.record(
        f"one core: every DDS service and topic matched the node's within "
        f"{DISCOVERY_TIMEOUT:.0f} s", [f"not matched: {', '.join(missing)}"] if missing else [])
    if missing:
        return checks
    host, port = address.rsplit(":", 1)
    check_one_core(peer, checks, host, int(port))
    return checks


# ---- without a node: the wrappers' bytes


def self_test():
    """The wrappers write the request header's 16 bytes after the encapsulation header and then
    exactly the plain message's body; the malformed requests are what they claim to be."""
    checks = Checks()
    guid, seq = 0x1122334455667788, 0x0102030405060709
    header = guid.to_bytes(8, "little") + seq.to_bytes(8, "little")
    scene = bytes(range(16))
    status = CooperateStatus(Time(9, 999_999_999), UUID(scene), Module(8), True, False,
                             Command(1), State(1), False, 10.25, 20.5)
    policies = [CooperationPolicy("lane-change", "", 1),
                CooperationPolicy("avoidance", "return", 2)]
    pairs = [
        ("set_commands request",
         SetCooperationCommandsRequest([CooperationCommand(UUID(scene), CooperationDecision(2))]),
         SetCommandsCall),
        ("set_commands response",
         SetCooperationCommandsResponse(ResponseStatus(False, 50004, "x")), SetCommandsReply),
        ("set_policies request", SetCooperationPoliciesRequest(policies), SetPoliciesCall),
        ("set_policies response", SetCooperationPoliciesResponse(SUCCESS), SetPoliciesReply),
        ("get_policies request", GetCooperationPoliciesRequest(0), GetPoliciesCall),
        ("get_policies response", GetCooperationPoliciesResponse(SUCCESS, policies),
         GetPoliciesReply),
        ("sync request",
         SyncCooperateStatusRequest("lane_change_left", [status],
                                    [StatedSequence(UUID(scene), "change")], [UUID(scene)]),
         SyncCall),
        ("sync response",
         SyncCooperateStatusResponse(
             True, "", [SyncResult(UUID(scene), True, "")],
             CooperateStatusArray(Time(1, 2), [status]),
             [Activation(UUID(scene), True, False, True)]),
         SyncReply),
    ]
    for name, plain, wrapper in pairs:
        def same(plain=plain, wrapper=wrapper):
            fields = [getattr(plain, f.name) for f in dataclasses.fields(plain)]
            body = plain.serialize()
            wrapped = wrapper(guid, seq, *fields).serialize()
            problems = []
            if wrapper.__idl_typename__ != plain.__idl_typename__:
                problems.append(f"type {wrapper.__idl_typename__} != {plain.__idl_typename__}")
            if body[:4] != b"\x00\x01\x00\x00" or wrapped[:4] != body[:4]:
                problems.append(f"encapsulation {wrapped[:4].hex()} / {body[:4].hex()}")
            if wrapped[4:20] != header:
                problems.append(f"header {wrapped[4:20].hex()} != {header.hex()}")
            if wrapped[20:] != body[4:]:
                problems.append(f"body {wrapped[20:].hex()} != {body[4:].hex()}")
            back = wrapper.deserialize(wrapped)
            if (back.guid, back.seq) != (guid, seq) or diff(plain, back, name):
                problems.append("does not read back")
            return problems

        checks.run(f"self-test: the {name} wrapper is the header, then the message", same)

    def malformed():
        problems = []
        short = SetCommandsCallShort(guid, seq, 1).serialize()
        if short[20:] != (1).to_bytes(4, "little"):
            problems.append(f"short set_commands body {short[20:].hex()}")
        no_nul = SetPoliciesCallNoNul(
            guid, seq, [PolicyWithoutNul(list(b"abc"), "", 2)]).serialize()
        if no_nul[20:32] != bytes.fromhex("01000000" "03000000" "616263") + b"\x00":
            problems.append(f"no-NUL set_policies body {no_nul[20:].hex()}")
        long = GetPoliciesCallLong(guid, seq, 0, 7).serialize()
        if len(long) - 20 != 16:
            problems.append(f"long get_policies body {long[20:].hex()}")
        good = SyncCall(guid, seq, "crosswalk", [status], [], []).serialize()
        bad = SyncCallBadBoolean(guid, seq, "crosswalk", [CooperateStatusByteSafe(
            status.stamp, status.uuid, status.module, 2, status.requested, status.command_status,
            status.state, status.auto_mode, status.start_distance, status.finish_distance)],
            [], []).serialize()
        changed = [at for at, (a, b) in enumerate(zip(good, bad)) if a != b]
        if len(good) != len(bad) or len(changed) != 1 or bad[changed[0]] != 2:
            problems.append(f"the bad boolean differs from a good sync at {changed}")
        return problems

    checks.run("self-test: the malformed requests differ from good ones only where meant",
               malformed)
    return checks


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--domain", type=int, default=42, help="the DDS domain (default 42)")
    parser.add_argument("--distro", choices=("humble", "jazzy"), default="humble",
                        help="the node's --distro: the size of a gid (24 bytes, or 16 for jazzy)")
    parser.add_argument("--self-test", action="store_true",
                        help="check the wrapper types' bytes only, with no node")
    parser.add_argument("--one-core", metavar="HOST:PORT",
                        help="check cooperation-server --dds-domain instead: its DDS door here, "
                             "its rosbridge door at HOST:PORT, one core")
    args = parser.parse_args()
    if args.self_test:
        checks = self_test()
    elif args.one_core:
        checks = one_core(args.domain, args.one_core)
    else:
        checks = interop(args.domain, args.distro)
    print(f"ros2 interop peer: {checks.passed} passed, {checks.failed} failed", flush=True)
    sys.exit(1 if checks.failed else 0)


if __name__ == "__main__":
    main()
