"""Upstream's `rtc_interface`, as `upstream-rtc.md` (§3.2 to §3.6, §6) states it, and the
`tier4_rtc_msgs` types its endpoints carry (§3.1), declared from the message definitions.

`RtcInterface` keeps a list of statuses searched by UUID (the first match wins), the stored
commands and the module's auto-mode flag; its functions are upstream's, quirks included:

- a new UUID is registered WAITING_FOR_EXECUTION whatever state is asked, with command
  DEACTIVATE and `auto_mode` the module's flag;
- an update the transition table refuses changes nothing, not even the stamp;
- a command is taken for a registered scene in WAITING_FOR_EXECUTION or RUNNING, and sets that
  scene's command and turns its `auto_mode` off; while the interface is locked the whole request
  replaces the stored commands, applied (again) at every unlock;
- the auto-mode service sets the flag and every scene's `auto_mode`, and always succeeds;
- `is_activated`: unknown or finished → false; auto mode and not requested → safe; else the
  command is ACTIVATE.
"""

from dataclasses import dataclass

from cdr_golden import RTC, Command, CooperateStatus, CooperateStatusArray, Module, State, Time
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import int64, sequence, uint64
from cdr_golden import UUID

# tier4_rtc_msgs/Command, State
DEACTIVATE, ACTIVATE = 0, 1
WAITING, RUNNING, ABORTING, SUCCEEDED, FAILED = 0, 1, 2, 3, 4
# tier4_rtc_msgs/Module; NONE is what an interface name upstream does not know reports
NONE, LANE_CHANGE_LEFT, AVOIDANCE_LEFT, TRAFFIC_LIGHT, INTERSECTION = 0, 1, 3, 7, 8

# How long a status lives without an accepted update, in seconds (strictly more expires).
EXPIRY = 10.0


@dataclass
class CooperateCommand(IdlStruct, typename=RTC.format("msg", "CooperateCommand")):
    uuid: UUID
    module: Module
    command: Command


@dataclass
class CooperateResponse(IdlStruct, typename=RTC.format("msg", "CooperateResponse")):
    uuid: UUID
    module: Module
    success: bool


@dataclass
class AutoModeStatus(IdlStruct, typename=RTC.format("msg", "AutoModeStatus")):
    module: Module
    is_auto_mode: bool


# The services' samples as rmw_cyclonedds_cpp writes them: the request header (the client's
# identifier, the call's sequence number), then the message's fields.


@dataclass
class CommandsCall(IdlStruct, typename=RTC.format("srv", "CooperateCommands_Request")):
    guid: uint64
    seq: int64
    stamp: Time
    commands: sequence[CooperateCommand]


@dataclass
class CommandsReply(IdlStruct, typename=RTC.format("srv", "CooperateCommands_Response")):
    guid: uint64
    seq: int64
    responses: sequence[CooperateResponse]


@dataclass
class AutoModeCall(IdlStruct, typename=RTC.format("srv", "AutoMode_Request")):
    guid: uint64
    seq: int64
    enable: bool


@dataclass
class AutoModeReply(IdlStruct, typename=RTC.format("srv", "AutoMode_Response")):
    guid: uint64
    seq: int64
    success: bool


def transition_allowed(current, wanted):
    """§3.6's four rules."""
    return ((current == WAITING and wanted in (WAITING, RUNNING, FAILED))
            or (current == RUNNING and wanted != WAITING)
            or (current == ABORTING and wanted in (ABORTING, FAILED))
            or wanted == current)


def seconds(stamp):
    return stamp.sec + stamp.nanosec * 1e-9


class RtcInterface:
    def __init__(self, name, module, enable_rtc):
        self.name = name
        self.module = module
        self.auto_mode = not enable_rtc
        self.locked = False
        self.statuses = []
        self.stored = []
        self.warnings = []

    def find(self, uuid):
        for status in self.statuses:
            if bytes(status.uuid.uuid) == uuid:
                return status
        return None

    def update(self, uuid, safe, state, start, finish, stamp, requested=False):
        status = self.find(uuid)
        if status is None:
            if state != WAITING:
                self.warnings.append(f"Cannot register {state} as initial state")
            self.statuses.append(CooperateStatus(
                stamp, UUID(uuid), Module(self.module), safe, requested, Command(DEACTIVATE),
                State(WAITING), self.auto_mode, start, finish))
            return
        if not transition_allowed(status.state.type, state):
            self.warnings.append(f"cannot transit from {status.state.type} to {state}")
            return
        status.stamp, status.safe, status.requested = stamp, safe, requested
        status.state = State(state)
        status.start_distance, status.finish_distance = start, finish

    def remove(self, uuid):
        for index, command in enumerate(self.stored):
            if bytes(command.uuid.uuid) == uuid:
                del self.stored[index]
                break
        self.statuses = [s for s in self.statuses if bytes(s.uuid.uuid) != uuid]

    def remove_expired(self, now):
        self.statuses = [s for s in self.statuses if seconds(now) - seconds(s.stamp) <= EXPIRY]

    def clear(self):
        self.statuses = []
        self.stored = []

    def is_activated(self, uuid):
        status = self.find(uuid)
        if status is None or status.state.type in (SUCCEEDED, FAILED):
            return False
        if status.auto_mode and not status.requested:
            return status.safe
        return status.command_status.type == ACTIVATE

    def array(self, stamp):
        return CooperateStatusArray(stamp, list(self.statuses))

    def auto_mode_status(self):
        return AutoModeStatus(Module(self.module), self.auto_mode)

    def apply(self, commands):
        for command in commands:
            status = self.find(bytes(command.uuid.uuid))
            if status is not None and status.state.type in (WAITING, RUNNING):
                status.command_status = Command(command.command.type)
                status.auto_mode = False

    def on_commands(self, commands):
        responses = []
        for command in commands:
            status = self.find(bytes(command.uuid.uuid))
            success = status is not None and status.state.type in (WAITING, RUNNING)
            responses.append(CooperateResponse(command.uuid, command.module, success))
        if self.locked:
            self.stored = list(commands)
        else:
            self.apply(commands)
        return responses

    def on_auto_mode(self, enable):
        self.auto_mode = enable
        for status in self.statuses:
            status.auto_mode = enable
        return True

    def lock(self):
        self.locked = True

    def unlock(self):
        self.locked = False
        self.apply(self.stored)
