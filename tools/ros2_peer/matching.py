"""Comparing what the node answers and publishes with what is expected (`diff`, with matchers
for the values that are a condition), the expected answers of the checks, and `Checks`, which
records each check's result as one line.
"""

import dataclasses
import time
import traceback

from .dds import PUBLICATION_TIMEOUT, uuid_text
from .messages import (
    PARAMETER_ERROR,
    Command,
    CooperateStatus,
    CooperateStatusArray,
    CooperationDecision,
    CooperationStatus,
    IDENTITY,
    Module,
    ResponseStatus,
    State,
    SteeringFactor,
    SyncCooperateStatusResponse,
    SyncResult,
    UUID,
    VelocityFactor,
)

# ---- comparing messages


class Matcher:
    """An expected value that is a condition rather than one value."""

    def mismatch(self, actual):
        raise NotImplementedError


class RecentStamp(Matcher):
    """A `builtin_interfaces/Time` within `tolerance` seconds of the wall clock now."""

    def __init__(self, tolerance=3.0):
        self.tolerance = tolerance

    def mismatch(self, actual):
        sec, nanosec = getattr(actual, "sec", None), getattr(actual, "nanosec", None)
        if not isinstance(sec, int) or not isinstance(nanosec, int):
            return f"not a time: {actual!r}"
        if not 0 <= nanosec < 1_000_000_000:
            return f"nanosec {nanosec} is not below 1e9"
        off = sec + nanosec * 1e-9 - time.time()
        if abs(off) > self.tolerance:
            return f"{sec}.{nanosec:09d} is {off:+.3f} s from the wall clock"
        return None

    def __repr__(self):
        return f"<within {self.tolerance} s of now>"


class Any(Matcher):
    def mismatch(self, actual):
        return None

    def __repr__(self):
        return "<any>"


class Contains(Matcher):
    def __init__(self, text):
        self.text = text

    def mismatch(self, actual):
        if isinstance(actual, str) and self.text in actual:
            return None
        return f"{actual!r} does not contain {self.text!r}"

    def __repr__(self):
        return f"<containing {self.text!r}>"


class StartsWith(Matcher):
    def __init__(self, text):
        self.text = text

    def mismatch(self, actual):
        if isinstance(actual, str) and actual.startswith(self.text):
            return None
        return f"{actual!r} does not start with {self.text!r}"

    def __repr__(self):
        return f"<starting with {self.text!r}>"


class NonEmpty(Matcher):
    def mismatch(self, actual):
        if isinstance(actual, str) and actual:
            return None
        return f"{actual!r} is empty"

    def __repr__(self):
        return "<non-empty text>"


def short(value, limit=160):
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def diff(expected, actual, path):
    """Every difference between `expected` and `actual`, each as `path: what`. Fields are
    compared by name, so a plain message's expected value is compared with a wrapper."""
    if isinstance(expected, Matcher):
        problem = expected.mismatch(actual)
        return [f"{path}: {problem}"] if problem else []
    if dataclasses.is_dataclass(expected) and not isinstance(expected, type):
        if not dataclasses.is_dataclass(actual):
            return [f"{path}: expected a {type(expected).__name__}, got {short(actual)}"]
        out = []
        for field in dataclasses.fields(expected):
            if not hasattr(actual, field.name):
                out.append(f"{path}.{field.name}: missing")
                continue
            out += diff(getattr(expected, field.name), getattr(actual, field.name),
                        f"{path}.{field.name}")
        return out
    if isinstance(expected, (bytes, bytearray)):
        try:
            got = bytes(actual)
        except (TypeError, ValueError):
            return [f"{path}: expected bytes {expected.hex()}, got {short(actual)}"]
        return [] if got == bytes(expected) else [
            f"{path}: expected {bytes(expected).hex()}, got {got.hex()}"]
    if isinstance(expected, (list, tuple)):
        if not isinstance(actual, (list, tuple)):
            return [f"{path}: expected a list, got {short(actual)}"]
        if len(actual) != len(expected):
            return [f"{path}: {len(actual)} entries, expected {len(expected)}: "
                    f"{short(actual, 400)}"]
        out = []
        for at, (e, a) in enumerate(zip(expected, actual)):
            out += diff(e, a, f"{path}[{at}]")
        return out
    if isinstance(expected, bool) or isinstance(actual, bool):
        return [] if type(actual) is type(expected) and actual == expected else [
            f"{path}: expected {expected!r}, got {actual!r}"]
    if expected != actual:
        return [f"{path}: expected {expected!r}, got {actual!r}"]
    return []


# ---- checks


class Checks:
    def __init__(self):
        self.passed = 0
        self.failed = 0

    def record(self, name, problems):
        if isinstance(problems, str):
            problems = [problems]
        problems = [p for p in (problems or []) if p]
        if problems:
            self.failed += 1
            why = "; ".join(problems[:6])
            if len(problems) > 6:
                why += f"; and {len(problems) - 6} more"
            print(f"FAIL {name}: {why}", flush=True)
        else:
            self.passed += 1
            print(f"PASS {name}", flush=True)
        return not problems

    def run(self, name, function):
        """Records `function()`'s problems (None or [] for none) as one check; an exception is
        a failure of the check, not of the run."""
        try:
            problems = function()
        except Exception as error:  # noqa: BLE001
            last = traceback.format_exception(error)[-1].strip()
            where = traceback.extract_tb(error.__traceback__)[-1]
            problems = [f"{last} (line {where.lineno})"]
        return self.record(name, problems)


# ---- the expected answers

def no_reply(client):
    return f"{client.service}: {client.unanswered}"


def status_problems(reply, expected, client):
    if reply is None:
        return [no_reply(client)]
    return diff(expected, reply.status, "status")


def refusal(contains=None):
    message = Contains(contains) if contains else NonEmpty()
    return ResponseStatus(False, PARAMETER_ERROR, message)


def factor_uuids(message):
    return [bytes(f.cooperation[0].uuid.uuid) for f in message.factors if f.cooperation]


def factor_of(message, scene):
    for factor in message.factors:
        if factor.cooperation and bytes(factor.cooperation[0].uuid.uuid) == scene:
            return factor
    return None


def cooperation(scene, autonomous, cooperator, cancellable=True):
    return [CooperationStatus(UUID(scene), CooperationDecision(autonomous),
                              CooperationDecision(cooperator), cancellable)]


def velocity_factor(scene, distance, behavior, autonomous, cooperator):
    return VelocityFactor(IDENTITY, distance, 0, behavior, "", "",
                          cooperation(scene, autonomous, cooperator))


def steering_factor(scene, start, finish, direction, behavior, sequence_, autonomous, cooperator):
    return SteeringFactor([IDENTITY, IDENTITY], [start, finish], direction, 0, behavior,
                          sequence_, "", cooperation(scene, autonomous, cooperator))


def node_status(scene, module, safe, state, start, finish, command, auto_mode, requested=False):
    """A status as the node answers it in a sync (stamp: the owner's last report)."""
    return CooperateStatus(RecentStamp(15.0), UUID(scene), Module(module), safe, requested,
                           Command(command), State(state), auto_mode, start, finish)


def sync_answer(results, statuses, activations, success=True, message=""):
    """The expected sync response; statuses and activations are in identifier order."""
    statuses = sorted(statuses, key=lambda s: bytes(s.uuid.uuid))
    activations = sorted(activations, key=lambda a: bytes(a.uuid.uuid))
    return SyncCooperateStatusResponse(
        success, message, [SyncResult(UUID(u), ok, m) for u, ok, m in results],
        CooperateStatusArray(RecentStamp(), statuses), activations)


def sync_problems(reply, expected, client):
    if reply is None:
        return [no_reply(client)]
    return diff(expected, reply, "response")


def factors_problems(stream, expected, wanted, after=None, timeout=PUBLICATION_TIMEOUT):
    """Waits for a publication listing exactly the scenes `wanted` (in any order) and compares
    it, every field, with `expected` (the header's stamp: the wall clock now)."""
    wanted = set(wanted)
    message = stream.wait(lambda m: set(factor_uuids(m)) == wanted, timeout, after)
    if message is None:
        newest = stream.newest()
        listed = [uuid_text(u) for u in factor_uuids(newest)] if newest else None
        errors = f"; reader errors: {'; '.join(stream.errors[-2:])}" if stream.errors else ""
        return [f"no publication on {stream.topic} listing exactly "
                f"{sorted(uuid_text(u) for u in wanted)} within {timeout} s (newest lists "
                f"{listed}){errors}"]
    return diff(expected, message, stream.topic)


def policies_of(reply):
    return {(p.behavior, p.sequence): p.policy for p in reply.policies}
