"""The message types the peer sends and reads: those of `tools/cdr_golden.py` (which
`adapters/tests/cdr.rs` holds the node's encoder to), imported from it, and those declared here: the
sync service's types, the request/reply wrappers as `rmw_cyclonedds_cpp` writes them, and the
malformed requests; then the messages' constants.
"""

from dataclasses import dataclass

from cdr_golden import (  # noqa: F401 (the types the other modules import from here)
    ADAPI,
    RTC,
    Command,
    CooperateStatus,
    CooperateStatusArray,
    CooperationCommand,
    CooperationDecision,
    CooperationPolicy,
    CooperationStatus,
    GetCooperationPoliciesRequest,
    GetCooperationPoliciesResponse,
    Header,
    Module,
    Point,
    Pose,
    Quaternion,
    ResponseStatus,
    SetCooperationCommandsRequest,
    SetCooperationCommandsResponse,
    SetCooperationPoliciesRequest,
    SetCooperationPoliciesResponse,
    State,
    SteeringFactor,
    SteeringFactorArray,
    Time,
    UUID,
    VelocityFactor,
    VelocityFactorArray,
)
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import (
    array,
    float32,
    int64,
    sequence,
    uint8,
    uint32,
    uint64,
)

# ---- cooperation_server: the planning modules' sync service (server/srv, server/msg)

SERVER = "cooperation_server::{}::dds_::{}_"


@dataclass
class StatedSequence(IdlStruct, typename=SERVER.format("msg", "StatedSequence")):
    uuid: UUID
    sequence: str


@dataclass
class SyncResult(IdlStruct, typename=SERVER.format("msg", "SyncResult")):
    uuid: UUID
    success: bool
    message: str


@dataclass
class Activation(IdlStruct, typename=SERVER.format("msg", "Activation")):
    uuid: UUID
    activated: bool
    force_activated: bool
    force_deactivated: bool


@dataclass
class SyncCooperateStatusRequest(
    IdlStruct, typename=SERVER.format("srv", "SyncCooperateStatus_Request")
):
    interface: str
    statuses: sequence[CooperateStatus]
    sequences: sequence[StatedSequence]
    removed: sequence[UUID]


@dataclass
class SyncCooperateStatusResponse(
    IdlStruct, typename=SERVER.format("srv", "SyncCooperateStatus_Response")
):
    success: bool
    message: str
    results: sequence[SyncResult]
    statuses: CooperateStatusArray
    activations: sequence[Activation]


# ---- rmw_dds_common: the ROS graph

DDS_COMMON = "rmw_dds_common::msg::dds_::{}_"


@dataclass
class Gid24(IdlStruct, typename=DDS_COMMON.format("Gid")):
    """`rmw_dds_common/Gid` up to Iron: 24 bytes, the entity's GUID then zeros."""

    data: array[uint8, 24]


@dataclass
class Gid16(IdlStruct, typename=DDS_COMMON.format("Gid")):
    """`rmw_dds_common/Gid` from Jazzy on: the entity's 16-byte GUID."""

    data: array[uint8, 16]


@dataclass
class NodeEntitiesInfo24(IdlStruct, typename=DDS_COMMON.format("NodeEntitiesInfo")):
    node_namespace: str
    node_name: str
    reader_gid_seq: sequence[Gid24]
    writer_gid_seq: sequence[Gid24]


@dataclass
class ParticipantEntitiesInfo24(IdlStruct, typename=DDS_COMMON.format("ParticipantEntitiesInfo")):
    gid: Gid24
    node_entities_info_seq: sequence[NodeEntitiesInfo24]


@dataclass
class NodeEntitiesInfo16(IdlStruct, typename=DDS_COMMON.format("NodeEntitiesInfo")):
    node_namespace: str
    node_name: str
    reader_gid_seq: sequence[Gid16]
    writer_gid_seq: sequence[Gid16]


@dataclass
class ParticipantEntitiesInfo16(IdlStruct, typename=DDS_COMMON.format("ParticipantEntitiesInfo")):
    gid: Gid16
    node_entities_info_seq: sequence[NodeEntitiesInfo16]


# ---- requests and replies as rmw_cyclonedds_cpp writes them
#
# A request or reply sample is the request header, `uint64 guid` (the client's) and `int64 seq`
# (the call's), then the message's fields, under the message's own DDS type name. Declared as
# one struct whose first two fields are the header, its XCDR1 bytes are the header's sixteen
# followed by the message's, at the same alignment (`--self-test` checks it).


@dataclass
class SetCommandsCall(IdlStruct, typename=ADAPI.format("srv", "SetCooperationCommands_Request")):
    guid: uint64
    seq: int64
    commands: sequence[CooperationCommand]


@dataclass
class SetCommandsReply(IdlStruct, typename=ADAPI.format("srv", "SetCooperationCommands_Response")):
    guid: uint64
    seq: int64
    status: ResponseStatus


@dataclass
class SetPoliciesCall(IdlStruct, typename=ADAPI.format("srv", "SetCooperationPolicies_Request")):
    guid: uint64
    seq: int64
    policies: sequence[CooperationPolicy]


@dataclass
class SetPoliciesReply(IdlStruct, typename=ADAPI.format("srv", "SetCooperationPolicies_Response")):
    guid: uint64
    seq: int64
    status: ResponseStatus


@dataclass
class GetPoliciesCall(IdlStruct, typename=ADAPI.format("srv", "GetCooperationPolicies_Request")):
    guid: uint64
    seq: int64
    structure_needs_at_least_one_member: uint8


@dataclass
class GetPoliciesReply(IdlStruct, typename=ADAPI.format("srv", "GetCooperationPolicies_Response")):
    guid: uint64
    seq: int64
    status: ResponseStatus
    policies: sequence[CooperationPolicy]


@dataclass
class SyncCall(IdlStruct, typename=SERVER.format("srv", "SyncCooperateStatus_Request")):
    guid: uint64
    seq: int64
    interface: str
    statuses: sequence[CooperateStatus]
    sequences: sequence[StatedSequence]
    removed: sequence[UUID]


@dataclass
class SyncReply(IdlStruct, typename=SERVER.format("srv", "SyncCooperateStatus_Response")):
    guid: uint64
    seq: int64
    success: bool
    message: str
    results: sequence[SyncResult]
    statuses: CooperateStatusArray
    activations: sequence[Activation]


# ---- malformed requests: the same DDS type names, bodies the node's strict CDR reader refuses
# (adapters/src/cdr/de.rs), each with a readable request header


@dataclass
class SetCommandsCallShort(
    IdlStruct, typename=ADAPI.format("srv", "SetCooperationCommands_Request")
):
    """A `commands` count of 1 and no command after it: the message ends early."""

    guid: uint64
    seq: int64
    count: uint32


@dataclass
class PolicyWithoutNul(IdlStruct, typename=ADAPI.format("msg", "CooperationPolicy")):
    """A policy whose `behavior` string has no final NUL (its bytes written as a sequence)."""

    behavior: sequence[uint8]
    sequence: str
    policy: uint8


@dataclass
class SetPoliciesCallNoNul(
    IdlStruct, typename=ADAPI.format("srv", "SetCooperationPolicies_Request")
):
    guid: uint64
    seq: int64
    policies: sequence[PolicyWithoutNul]


@dataclass
class GetPoliciesCallLong(
    IdlStruct, typename=ADAPI.format("srv", "GetCooperationPolicies_Request")
):
    """The request's one byte, then fifteen more: more than three bytes follow the message."""

    guid: uint64
    seq: int64
    structure_needs_at_least_one_member: uint8
    extra: uint64


@dataclass
class CooperateStatusByteSafe(IdlStruct, typename=RTC.format("msg", "CooperateStatus")):
    """`tier4_rtc_msgs/CooperateStatus` with `safe` written as a byte, to send a boolean 2."""

    stamp: Time
    uuid: UUID
    module: Module
    safe: uint8
    requested: bool
    command_status: Command
    state: State
    auto_mode: bool
    start_distance: float32
    finish_distance: float32


@dataclass
class SyncCallBadBoolean(IdlStruct, typename=SERVER.format("srv", "SyncCooperateStatus_Request")):
    guid: uint64
    seq: int64
    interface: str
    statuses: sequence[CooperateStatusByteSafe]
    sequences: sequence[StatedSequence]
    removed: sequence[UUID]


# ---- the messages' constants

# autoware_adapi_v1_msgs/CooperationDecision
UNKNOWN, DEACTIVATE, ACTIVATE, AUTONOMOUS, UNDECIDED = 0, 1, 2, 3, 4
# autoware_adapi_v1_msgs/CooperationPolicy
OPTIONAL, REQUIRED = 1, 2
# autoware_adapi_v1_msgs/SteeringFactor.direction
LEFT, RIGHT = 1, 2
# tier4_rtc_msgs/State
WAITING, RUNNING, ABORTING, SUCCEEDED, FAILED = 0, 1, 2, 3, 4
# tier4_rtc_msgs/Command
RTC_DEACTIVATE, RTC_ACTIVATE = 0, 1
# tier4_rtc_msgs/Module
MODULE_LANE_CHANGE_LEFT, MODULE_AVOIDANCE_RIGHT, MODULE_INTERSECTION, MODULE_CROSSWALK = 1, 4, 8, 10
# autoware_adapi_v1_msgs/ResponseStatus.code
PARAMETER_ERROR, NO_EFFECT = 50004, 60001

IDENTITY = Pose(Point(0.0, 0.0, 0.0), Quaternion(0.0, 0.0, 0.0, 1.0))
SUCCESS = ResponseStatus(True, 0, "")
