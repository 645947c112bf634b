"""The golden CDR bytes of the messages, written by Cyclone DDS's own Python serializer
(`cyclonedds.idl`, PyPI), for `adapters/tests/cdr.rs` to compare the library's encoder with.

Each message is declared here as Cyclone's IDL types for the ROS 2 message (field for field,
the ROS 2 DDS type names), a sample value is made that `adapters/tests/cdr.rs` makes too, and its
serialized bytes are written as hex to `adapters/tests/data/cdr/<name>.hex`. With `--check`, the
files are compared instead, and any difference fails. Run by `tools/cdr-golden`.
"""

import sys
from dataclasses import dataclass, field
from pathlib import Path

from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, float32, float64, int32, sequence, uint8, uint16, uint32

# ---- builtin_interfaces, std_msgs, geometry_msgs, unique_identifier_msgs


@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


@dataclass
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time
    frame_id: str


@dataclass
class Point(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    x: float64
    y: float64
    z: float64


@dataclass
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    x: float64
    y: float64
    z: float64
    w: float64


@dataclass
class Pose(IdlStruct, typename="geometry_msgs::msg::dds_::Pose_"):
    position: Point
    orientation: Quaternion


@dataclass
class UUID(IdlStruct, typename="unique_identifier_msgs::msg::dds_::UUID_"):
    uuid: array[uint8, 16]


# ---- autoware_adapi_v1_msgs

ADAPI = "autoware_adapi_v1_msgs::{}::dds_::{}_"


@dataclass
class ResponseStatus(IdlStruct, typename=ADAPI.format("msg", "ResponseStatus")):
    success: bool
    code: uint16
    message: str


@dataclass
class CooperationDecision(IdlStruct, typename=ADAPI.format("msg", "CooperationDecision")):
    decision: uint8


@dataclass
class CooperationStatus(IdlStruct, typename=ADAPI.format("msg", "CooperationStatus")):
    uuid: UUID
    autonomous: CooperationDecision
    cooperator: CooperationDecision
    cancellable: bool


@dataclass
class CooperationCommand(IdlStruct, typename=ADAPI.format("msg", "CooperationCommand")):
    uuid: UUID
    cooperator: CooperationDecision


@dataclass
class CooperationPolicy(IdlStruct, typename=ADAPI.format("msg", "CooperationPolicy")):
    behavior: str
    sequence: str
    policy: uint8


@dataclass
class VelocityFactor(IdlStruct, typename=ADAPI.format("msg", "VelocityFactor")):
    pose: Pose
    distance: float32
    status: uint16
    behavior: str
    sequence: str
    detail: str
    cooperation: sequence[CooperationStatus, 1]


@dataclass
class VelocityFactorArray(IdlStruct, typename=ADAPI.format("msg", "VelocityFactorArray")):
    header: Header
    factors: sequence[VelocityFactor]


@dataclass
class SteeringFactor(IdlStruct, typename=ADAPI.format("msg", "SteeringFactor")):
    pose: array[Pose, 2]
    distance: array[float32, 2]
    direction: uint16
    status: uint16
    behavior: str
    sequence: str
    detail: str
    cooperation: sequence[CooperationStatus, 1]


@dataclass
class SteeringFactorArray(IdlStruct, typename=ADAPI.format("msg", "SteeringFactorArray")):
    header: Header
    factors: sequence[SteeringFactor]


@dataclass
class SetCooperationCommandsRequest(
    IdlStruct, typename=ADAPI.format("srv", "SetCooperationCommands_Request")
):
    commands: sequence[CooperationCommand]


@dataclass
class SetCooperationCommandsResponse(
    IdlStruct, typename=ADAPI.format("srv", "SetCooperationCommands_Response")
):
    status: ResponseStatus


@dataclass
class SetCooperationPoliciesRequest(
    IdlStruct, typename=ADAPI.format("srv", "SetCooperationPolicies_Request")
):
    policies: sequence[CooperationPolicy]


@dataclass
class SetCooperationPoliciesResponse(
    IdlStruct, typename=ADAPI.format("srv", "SetCooperationPolicies_Response")
):
    status: ResponseStatus


@dataclass
class GetCooperationPoliciesRequest(
    IdlStruct, typename=ADAPI.format("srv", "GetCooperationPolicies_Request")
):
    structure_needs_at_least_one_member: uint8


@dataclass
class GetCooperationPoliciesResponse(
    IdlStruct, typename=ADAPI.format("srv", "GetCooperationPolicies_Response")
):
    status: ResponseStatus
    policies: sequence[CooperationPolicy]


# ---- tier4_rtc_msgs

RTC = "tier4_rtc_msgs::{}::dds_::{}_"


@dataclass
class Module(IdlStruct, typename=RTC.format("msg", "Module")):
    type: uint8


@dataclass
class Command(IdlStruct, typename=RTC.format("msg", "Command")):
    type: uint8


@dataclass
class State(IdlStruct, typename=RTC.format("msg", "State")):
    type: uint8


@dataclass
class CooperateStatus(IdlStruct, typename=RTC.format("msg", "CooperateStatus")):
    stamp: Time
    uuid: UUID
    module: Module
    safe: bool
    requested: bool
    command_status: Command
    state: State
    auto_mode: bool
    start_distance: float32
    finish_distance: float32


@dataclass
class CooperateStatusArray(IdlStruct, typename=RTC.format("msg", "CooperateStatusArray")):
    stamp: Time
    statuses: sequence[CooperateStatus]


# ---- the samples (the same values as adapters/tests/cdr.rs)


def uuid(first):
    return UUID([(first + i) % 256 for i in range(16)])


def pose(x, y):
    return Pose(Point(x, y, 0.0), Quaternion(0.0, 0.0, 0.5, 0.5))


IDENTITY = Pose(Point(0.0, 0.0, 0.0), Quaternion(0.0, 0.0, 0.0, 1.0))

SAMPLES = {
    "velocity_factors": VelocityFactorArray(
        Header(Time(1_700_000_000, 123_456_789), "map"),
        [
            VelocityFactor(
                pose(1.5, -2.25), 12.5, 1, "intersection", "", "odd",
                [CooperationStatus(uuid(0), CooperationDecision(2), CooperationDecision(4), True)],
            ),
            VelocityFactor(IDENTITY, 3.0, 2, "crosswalk", "x", "", []),
        ],
    ),
    "steering_factors": SteeringFactorArray(
        Header(Time(5, 6), "base_link"),
        [
            SteeringFactor(
                [pose(10.0, 1.0), pose(60.0, 4.5)], [25.0, 70.5], 2, 3, "lane-change", "change",
                "a", [CooperationStatus(uuid(240), CooperationDecision(1), CooperationDecision(3), False)],
            )
        ],
    ),
    "set_commands_request": SetCooperationCommandsRequest(
        [
            CooperationCommand(uuid(0), CooperationDecision(2)),
            CooperationCommand(UUID([0xAB] * 16), CooperationDecision(4)),
        ]
    ),
    "set_commands_response": SetCooperationCommandsResponse(
        ResponseStatus(False, 50004, "commands[1].cooperator.decision is 9")
    ),
    "set_policies_request": SetCooperationPoliciesRequest(
        [CooperationPolicy("lane-change", "", 1), CooperationPolicy("avoidance", "return", 2)]
    ),
    "set_policies_response": SetCooperationPoliciesResponse(ResponseStatus(True, 0, "")),
    "get_policies_request": GetCooperationPoliciesRequest(0),
    "get_policies_response": GetCooperationPoliciesResponse(
        ResponseStatus(True, 0, ""), [CooperationPolicy("intersection", "", 2)]
    ),
    "cooperate_status_array": CooperateStatusArray(
        Time(10, 20),
        [
            CooperateStatus(
                Time(9, 999_999_999), uuid(1), Module(8), True, False, Command(1), State(1),
                False, 10.25, 10.25,
            )
        ],
    ),
}


def main():
    check = "--check" in sys.argv[1:]
    folder = Path(__file__).resolve().parent.parent / "adapters" / "tests" / "data" / "cdr"
    folder.mkdir(parents=True, exist_ok=True)
    differ = []
    for name, sample in SAMPLES.items():
        text = sample.serialize().hex() + "\n"
        path = folder / f"{name}.hex"
        if check:
            if not path.exists() or path.read_text() != text:
                differ.append(name)
        else:
            path.write_text(text)
    if check:
        for name in differ:
            print(f"{name}.hex differs from what cyclonedds.idl writes")
        print(f"{len(SAMPLES) - len(differ)} golden files match cyclonedds.idl, {len(differ)} differ")
        sys.exit(1 if differ else 0)
    print(f"wrote {len(SAMPLES)} golden files to {folder}")


if __name__ == "__main__":
    main()
