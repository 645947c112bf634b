"""roslibpy clients of a cooperation-server: an operator and a planning module, with bounded
waits for every answer and publication.

roslibpy (Twisted transport) runs one reactor thread per process; every callback below runs on
it, in the order the frames arrived. The reactor cannot be restarted, so connections are only
ever closed (`Connection.close`), never ``Ros.terminate``d.

roslibpy registers no handler for rosbridge ``status`` frames (it logs an exception for each);
`Connection` installs one and keeps them, so tests can assert on what the node said.
"""

import threading
import time
import uuid as uuidlib

import roslibpy

# The longest any single answer or publication is waited for, in seconds.
TIMEOUT = 5.0

# -- names -----------------------------------------------------------------------------------

SET_COMMANDS = ("/api/planning/cooperation/set_commands",
                "autoware_adapi_v1_msgs/srv/SetCooperationCommands")
SET_POLICIES = ("/api/planning/cooperation/set_policies",
                "autoware_adapi_v1_msgs/srv/SetCooperationPolicies")
GET_POLICIES = ("/api/planning/cooperation/get_policies",
                "autoware_adapi_v1_msgs/srv/GetCooperationPolicies")
SYNC = ("/cooperation/rtc/sync", "cooperation_server/srv/SyncCooperateStatus")
VELOCITY = ("/api/planning/velocity_factors", "autoware_adapi_v1_msgs/msg/VelocityFactorArray")
STEERING = ("/api/planning/steering_factors", "autoware_adapi_v1_msgs/msg/SteeringFactorArray")

# autoware_adapi_v1_msgs/CooperationDecision
DEACTIVATE, ACTIVATE, AUTONOMOUS, UNDECIDED = 1, 2, 3, 4
# autoware_adapi_v1_msgs/CooperationPolicy
OPTIONAL, REQUIRED = 1, 2
# autoware_adapi_v1_msgs/SteeringFactor.direction
LEFT, RIGHT = 1, 2
# tier4_rtc_msgs/State
WAITING, RUNNING, ABORTING, SUCCEEDED, FAILED = 0, 1, 2, 3, 4
# tier4_rtc_msgs/Command
RTC_DEACTIVATE, RTC_ACTIVATE = 0, 1
# autoware_adapi_v1_msgs/ResponseStatus.code
PARAMETER_ERROR = 50004


def new_uuid():
    """A fresh scene identifier, as the messages write it: a list of 16 numbers."""
    return list(uuidlib.uuid4().bytes)


def uuid_msg(uuid):
    return {"uuid": list(uuid)}


def same_uuid(message_uuid, uuid):
    return list(message_uuid["uuid"]) == list(uuid)


def wait_for(predicate, timeout, what, interval=0.01):
    """Polls ``predicate`` until it answers something true, for at most ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"{what}: not within {timeout} s")
        time.sleep(interval)


class Answer:
    """A service's answer: ``result`` is rosbridge's (False when the node refused the call, and
    ``values`` is then its message); ``mark`` is what the caller's ``mark`` function answered
    on the reactor thread as the answer arrived."""

    def __init__(self, result, values, mark=None):
        self.result = result
        self.values = values
        self.mark = mark

    def __repr__(self):
        return f"Answer(result={self.result!r}, values={self.values!r})"


class Connection:
    """One roslibpy connection to the node, with its ``status`` frames collected."""

    def __init__(self, port, host="127.0.0.1", timeout=TIMEOUT, token=None):
        self._statuses = []
        self._condition = threading.Condition()
        # A node with credentials takes the token as a bearer token when the WebSocket opens.
        headers = {"Authorization": f"Bearer {token}"} if token else None
        self.ros = roslibpy.Ros(host=host, port=port, headers=headers)
        # Installed as the connection opens, before any frame is read.
        self.ros.factory.on_ready(self._install_status_handler)
        try:
            self.ros.run(timeout=timeout)
        except BaseException:
            self.close()
            raise

    def _install_status_handler(self, protocol):
        # roslibpy reserves the "status" operation with no handler, so
        # `register_message_handlers` refuses it: replace the placeholder.
        if protocol._message_handlers.get("status") is None:
            protocol._message_handlers.pop("status", None)
            protocol.register_message_handlers("status", self._on_status)
        return protocol

    def _on_status(self, message):
        with self._condition:
            self._statuses.append(dict(message))
            self._condition.notify_all()

    def close(self, timeout=TIMEOUT):
        """Closes the connection and waits (bounded) until it is closed; never reconnects."""
        self.ros.factory.stopTrying()
        if self.ros.is_connected:
            self.ros.close(timeout)
            wait_for(lambda: not self.ros.is_connected, timeout, "the connection to close")

    # -- status frames -----------------------------------------------------------------------

    def statuses(self):
        with self._condition:
            return list(self._statuses)

    def wait_status(self, predicate, timeout=TIMEOUT, since=0):
        """The first status frame from index ``since`` on that satisfies ``predicate``."""
        with self._condition:
            def found():
                return next((s for s in self._statuses[since:] if predicate(s)), None)
            if not self._condition.wait_for(found, timeout):
                raise AssertionError(
                    f"no such status frame within {timeout} s; got {self._statuses[since:]!r}")
            return found()

    # -- frames ------------------------------------------------------------------------------

    def send(self, frame):
        """Sends a rosbridge frame (a dict) as roslibpy sends any frame."""
        self.ros.send_on_ready(roslibpy.Message(frame))

    def send_text(self, text, binary=False):
        """Sends raw text (or bytes in a binary frame) through roslibpy's protocol."""
        payload = text.encode("utf-8") if isinstance(text, str) else text

        def send(protocol):
            if binary:
                from twisted.internet import reactor
                reactor.callFromThread(protocol.sendMessage, payload, isBinary=True)
            else:
                protocol.send_message(payload)
            return protocol

        self.ros.factory.on_ready(send)

    # -- services ----------------------------------------------------------------------------

    def call(self, service, args=None, timeout=TIMEOUT, mark=None, type_name=None):
        """Calls ``service`` (a (name, type) pair) with ``args`` through ``roslibpy.Service``.

        With ``type_name`` the frame is built here instead, to carry a ``type`` (roslibpy's
        Service sends none). Raises AssertionError when no answer comes within ``timeout``.
        """
        name, service_type = service
        done = threading.Event()
        box = {}

        def answered(result, values):
            box["answer"] = Answer(result, values, mark() if mark else None)
            done.set()

        def callback(values):
            answered(True, dict(values))

        def errback(values):
            answered(False, values)

        if type_name is None:
            roslibpy.Service(self.ros, name, service_type).call(
                roslibpy.ServiceRequest(args or {}), callback, errback)
        else:
            frame = roslibpy.Message({
                "op": "call_service",
                "id": f"call_service:{name}:{self.ros.id_counter}",
                "service": name,
                "type": type_name,
                "args": args or {},
            })
            self.ros.call_async_service(frame, callback, errback)
        if not done.wait(timeout):
            raise AssertionError(f"no answer from {name} within {timeout} s")
        return box["answer"]

    def call_ok(self, service, args=None, **options):
        """A call the node must answer with ``result: true``; its values."""
        answer = self.call(service, args, **options)
        if not answer.result:
            raise AssertionError(f"{service[0]} refused the call: {answer.values!r}")
        return answer.values

    # -- topics ------------------------------------------------------------------------------

    def subscribe(self, topic):
        return Recorder(self, topic)


class Recorder:
    """A subscription that keeps every publication it receives, in order."""

    def __init__(self, connection, topic):
        self.name, self.type = topic
        self.condition = threading.Condition()
        self.messages = []
        self.topic = roslibpy.Topic(connection.ros, self.name, self.type)
        self.topic.subscribe(self._received)

    def _received(self, message):
        with self.condition:
            self.messages.append(message)
            self.condition.notify_all()

    def count(self):
        """How many publications arrived; call on the reactor thread (an Answer's ``mark``) to
        mark a point in the stream."""
        with self.condition:
            return len(self.messages)

    def since(self, index):
        """The publications from number ``index`` on, received so far."""
        with self.condition:
            return list(self.messages[index:])

    def at(self, index, timeout=TIMEOUT):
        """Publication number ``index`` (from 0), waiting for it."""
        with self.condition:
            if not self.condition.wait_for(lambda: len(self.messages) > index, timeout):
                raise AssertionError(
                    f"{self.name}: publication {index} not within {timeout} s "
                    f"({len(self.messages)} received)")
            return self.messages[index]

    def next(self, timeout=TIMEOUT):
        """The first publication received after this call."""
        return self.at(self.count(), timeout)

    def wait(self, predicate, timeout=TIMEOUT, since=None):
        """The first publication from index ``since`` (default: the next one) that satisfies
        ``predicate``."""
        start = self.count() if since is None else since
        with self.condition:
            def found():
                return next((m for m in self.messages[start:] if predicate(m)), None)
            if not self.condition.wait_for(found, timeout):
                last = self.messages[-1] if self.messages else None
                raise AssertionError(
                    f"{self.name}: no such publication within {timeout} s; last: {last!r}")
            return found()


def factor_of(message, uuid):
    """The factor of scene ``uuid`` in a factor array, or None."""
    for factor in message["factors"]:
        for cooperation in factor["cooperation"]:
            if same_uuid(cooperation["uuid"], uuid):
                return factor
    return None


def cooperation_of(message, uuid):
    factor = factor_of(message, uuid)
    return factor["cooperation"][0] if factor else None


# -- operator --------------------------------------------------------------------------------

def command(uuid, decision):
    return {"uuid": uuid_msg(uuid), "cooperator": {"decision": decision}}


def set_commands(connection, *commands, **options):
    return connection.call(SET_COMMANDS, {"commands": list(commands)}, **options)


def policy(behavior, value, sequence=""):
    return {"behavior": behavior, "sequence": sequence, "policy": value}


def get_policies(connection):
    values = connection.call_ok(GET_POLICIES, {})
    assert values["status"]["success"], values
    return {(p["behavior"], p["sequence"]): p["policy"] for p in values["policies"]}


# -- planning module -------------------------------------------------------------------------

def status(uuid, safe=True, state=WAITING, start=10.0, finish=50.0, requested=False):
    """A ``tier4_rtc_msgs/CooperateStatus`` as a module reports it; the node fills ``module``,
    ``command_status``, ``auto_mode`` and ``stamp``."""
    return {
        "stamp": {"sec": 0, "nanosec": 0},
        "uuid": uuid_msg(uuid),
        "module": {"type": 0},
        "safe": safe,
        "requested": requested,
        "command_status": {"type": 0},
        "state": {"type": state},
        "auto_mode": False,
        "start_distance": start,
        "finish_distance": finish,
    }


class Module:
    """A planning module: its own connection, syncing through one RTC interface."""

    def __init__(self, port, interface):
        self.interface = interface
        self.connection = Connection(port)

    def close(self):
        self.connection.close()

    def sync(self, statuses=(), sequences=(), removed=(), **options):
        """One sync; the response's values."""
        args = {"interface": self.interface, "statuses": list(statuses)}
        if sequences:
            args["sequences"] = [{"uuid": uuid_msg(u), "sequence": s} for u, s in sequences]
        if removed:
            args["removed"] = [uuid_msg(u) for u in removed]
        return self.connection.call_ok(SYNC, args, **options)


def activation_of(response, uuid):
    return next((a for a in response["activations"] if same_uuid(a["uuid"], uuid)), None)


def status_of(response, uuid):
    return next(
        (s for s in response["statuses"]["statuses"] if same_uuid(s["uuid"], uuid)), None)


# -- fixtures --------------------------------------------------------------------------------

def connect(test, port):
    """A `Connection` that ``test`` closes in its cleanup."""
    connection = Connection(port)
    test.addCleanup(connection.close)
    return connection


def module(test, port, interface):
    """A `Module` that ``test`` closes in its cleanup."""
    planner = Module(port, interface)
    test.addCleanup(planner.close)
    return planner
