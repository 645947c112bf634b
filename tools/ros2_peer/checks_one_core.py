"""One process, one core, every door: `cooperation-server --dds-domain`, reached at once over
rosbridge (an operator's panel, a planning module) and over DDS (ROS 2 clients), must show and
change the same scenes.

The rosbridge side is a minimal WebSocket client written here on the standard library (one
text frame per rosbridge message, as the node sends them), so that the check needs no package
beyond those of `tools/cdr-requirements.txt`.
"""

import base64
import json
import os
import socket
import struct
import time

from ros2_peer.dds import PUBLICATION_TIMEOUT, new_uuid, report
from ros2_peer.matching import factor_of
from ros2_peer.messages import (
    SUCCESS,
    WAITING,
    CooperationCommand,
    CooperationDecision,
    UUID,
)

# The AD API's CooperationDecision constants.
DEACTIVATE, ACTIVATE = 1, 2
WAIT = 5.0


class Rosbridge:
    """A rosbridge v2 client over a WebSocket on TCP, enough for calls and subscriptions."""

    def __init__(self, host, port):
        self.sock = socket.create_connection((host, port), timeout=WAIT)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall(
            (f"GET / HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
             f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
             "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(1)
            if not chunk:
                raise ConnectionError("closed during the handshake")
            head += chunk
        if not head.startswith(b"HTTP/1.1 101"):
            raise ConnectionError(head.split(b"\r\n")[0].decode(errors="replace"))
        self.next_id = 0

    def _read(self, n):
        data = b""
        while len(data) < n:
            chunk = self.sock.recv(n - len(data))
            if not chunk:
                raise ConnectionError("closed")
            data += chunk
        return data

    def send(self, message):
        payload = json.dumps(message).encode()
        mask = os.urandom(4)
        length = len(payload)
        if length < 126:
            header = struct.pack("!BB", 0x81, 0x80 | length)
        elif length < 1 << 16:
            header = struct.pack("!BBH", 0x81, 0x80 | 126, length)
        else:
            header = struct.pack("!BBQ", 0x81, 0x80 | 127, length)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        self.sock.sendall(header + mask + masked)

    def receive(self):
        """The next text message, as JSON; pings and other control frames are skipped."""
        while True:
            first, second = self._read(2)
            length = second & 0x7F
            if length == 126:
                length = struct.unpack("!H", self._read(2))[0]
            elif length == 127:
                length = struct.unpack("!Q", self._read(8))[0]
            payload = self._read(length)
            if first & 0x0F == 0x1:
                return json.loads(payload)

    def call(self, service, args):
        self.next_id += 1
        ident = f"call:{self.next_id}"
        self.send({"op": "call_service", "id": ident, "service": service, "args": args})
        deadline = time.monotonic() + WAIT
        while time.monotonic() < deadline:
            message = self.receive()
            if message.get("op") == "service_response" and message.get("id") == ident:
                return message
        raise TimeoutError(f"no answer from {service}")

    def wait_publication(self, topic, predicate):
        """The first publication of `topic` that `predicate` accepts, or None in time."""
        deadline = time.monotonic() + WAIT
        while time.monotonic() < deadline:
            message = self.receive()
            if message.get("op") == "publish" and message.get("topic") == topic \
                    and predicate(message["msg"]):
                return message["msg"]
        return None


def cooperator(msg, scene):
    """The cooperator decision a rosbridge factor message shows for `scene`, or None."""
    for factor in msg.get("factors", []):
        for status in factor.get("cooperation", []):
            if bytes(status["uuid"]["uuid"]) == scene:
                return status["cooperator"]["decision"]
    return None


def rosbridge_status(scene, safe, distance):
    return {"uuid": {"uuid": list(scene)}, "safe": safe, "state": {"type": WAITING},
            "start_distance": distance, "finish_distance": distance}


def check_one_core(peer, checks, host, port):
    """A module's scene reported over rosbridge is commanded over DDS, and the reverse; each
    door's streams show what the other door changed."""
    bridge = Rosbridge(host, port)
    velocity = "/api/planning/velocity_factors"
    bridge.send({"op": "subscribe", "topic": velocity})
    through_rosbridge, through_dds = new_uuid(), new_uuid()

    def reported_over_rosbridge():
        answer = bridge.call("/cooperation/rtc/sync", {
            "interface": "intersection",
            "statuses": [rosbridge_status(through_rosbridge, False, 25.0)]})
        values = answer.get("values", {})
        return [] if answer.get("result") and values.get("success") else [f"answer {answer}"]

    checks.run("one core: a module's scene reported over rosbridge registers", reported_over_rosbridge)

    def commanded_over_dds():
        reply = peer.set_commands.call(
            [CooperationCommand(UUID(through_rosbridge), CooperationDecision(ACTIVATE))])
        if reply is None:
            return ["no reply over DDS"]
        return [] if reply.status == SUCCESS else [f"status {reply.status}"]

    checks.run("one core: set_commands over DDS applies to the scene reported over rosbridge",
               commanded_over_dds)

    def shown_over_dds(scene, decision):
        def shows(message):
            factor = factor_of(message, scene)
            return factor is not None and factor.cooperation[0].cooperator.decision == decision

        found = peer.velocity.wait(shows, PUBLICATION_TIMEOUT)
        return [] if found is not None else [f"no DDS publication showed decision {decision}"]

    checks.run("one core: the DDS factors show the operator decision made over DDS",
               lambda: shown_over_dds(through_rosbridge, ACTIVATE))

    def shown_over_rosbridge():
        found = bridge.wait_publication(
            velocity, lambda msg: cooperator(msg, through_rosbridge) == ACTIVATE)
        return [] if found is not None else ["no rosbridge publication showed the ACTIVATE"]

    checks.run("one core: the rosbridge factors show the operator decision made over DDS",
               shown_over_rosbridge)

    def reported_over_dds():
        reply = peer.sync.call("crosswalk",
                               [report(through_dds, True, WAITING, 40.0, 40.0)], [], [])
        if reply is None:
            return ["no reply over DDS"]
        return [] if reply.success else [f"{reply.message} {reply.results}"]

    checks.run("one core: a module's scene reported over DDS registers", reported_over_dds)

    def commanded_over_rosbridge():
        answer = bridge.call("/api/planning/cooperation/set_commands", {"commands": [
            {"uuid": {"uuid": list(through_dds)}, "cooperator": {"decision": DEACTIVATE}}]})
        status = answer.get("values", {}).get("status", {})
        return [] if status.get("success") else [f"answer {answer}"]

    checks.run("one core: set_commands over rosbridge applies to the scene reported over DDS",
               commanded_over_rosbridge)

    checks.run("one core: the DDS factors show the operator decision made over rosbridge",
               lambda: shown_over_dds(through_dds, DEACTIVATE))
