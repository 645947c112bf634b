// The messages of upstream's RTC interface as plain structs, for a build without ROS 2: the
// same namespaces, names, members and constants as the generated `tier4_rtc_msgs`,
// `unique_identifier_msgs` and `builtin_interfaces` types, so that a planning module's code
// compiles against either. Not included where rclcpp is present (COOPERATION_RTC_WITH_RCLCPP):
// the generated types are used there.
#ifndef COOPERATION__RTC__MESSAGES_HPP_
#define COOPERATION__RTC__MESSAGES_HPP_

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace builtin_interfaces::msg
{
/// `builtin_interfaces/Time`.
struct Time
{
  int32_t sec = 0;
  uint32_t nanosec = 0;
};
}  // namespace builtin_interfaces::msg

namespace unique_identifier_msgs::msg
{
/// `unique_identifier_msgs/UUID`.
struct UUID
{
  std::array<uint8_t, 16> uuid{};
};
}  // namespace unique_identifier_msgs::msg

namespace tier4_rtc_msgs::msg
{
/// `tier4_rtc_msgs/Command`.
struct Command
{
  static constexpr uint8_t DEACTIVATE = 0;
  static constexpr uint8_t ACTIVATE = 1;
  uint8_t type = DEACTIVATE;
};

/// `tier4_rtc_msgs/State`.
struct State
{
  static constexpr uint8_t WAITING_FOR_EXECUTION = 0;
  static constexpr uint8_t RUNNING = 1;
  static constexpr uint8_t ABORTING = 2;
  static constexpr uint8_t SUCCEEDED = 3;
  static constexpr uint8_t FAILED = 4;
  uint8_t type = WAITING_FOR_EXECUTION;
};

/// `tier4_rtc_msgs/Module`.
struct Module
{
  static constexpr uint8_t NONE = 0;
  static constexpr uint8_t LANE_CHANGE_LEFT = 1;
  static constexpr uint8_t LANE_CHANGE_RIGHT = 2;
  static constexpr uint8_t AVOIDANCE_LEFT = 3;
  static constexpr uint8_t AVOIDANCE_RIGHT = 4;
  static constexpr uint8_t GOAL_PLANNER = 5;
  static constexpr uint8_t START_PLANNER = 6;
  static constexpr uint8_t TRAFFIC_LIGHT = 7;
  static constexpr uint8_t INTERSECTION = 8;
  static constexpr uint8_t INTERSECTION_OCCLUSION = 9;
  static constexpr uint8_t CROSSWALK = 10;
  static constexpr uint8_t BLIND_SPOT = 11;
  static constexpr uint8_t DETECTION_AREA = 12;
  static constexpr uint8_t NO_STOPPING_AREA = 13;
  static constexpr uint8_t OCCLUSION_SPOT = 14;
  static constexpr uint8_t EXT_REQUEST_LANE_CHANGE_LEFT = 15;
  static constexpr uint8_t EXT_REQUEST_LANE_CHANGE_RIGHT = 16;
  static constexpr uint8_t AVOIDANCE_BY_LC_LEFT = 17;
  static constexpr uint8_t AVOIDANCE_BY_LC_RIGHT = 18;
  static constexpr uint8_t ROUNDABOUT = 19;
  uint8_t type = NONE;
};

/// `tier4_rtc_msgs/CooperateStatus`.
struct CooperateStatus
{
  builtin_interfaces::msg::Time stamp;
  unique_identifier_msgs::msg::UUID uuid;
  Module module;
  bool safe = false;
  bool requested = false;
  Command command_status;
  State state;
  bool auto_mode = false;
  float start_distance = 0.0F;
  float finish_distance = 0.0F;
};

/// `tier4_rtc_msgs/CooperateStatusArray`.
struct CooperateStatusArray
{
  builtin_interfaces::msg::Time stamp;
  std::vector<CooperateStatus> statuses;
};

/// `tier4_rtc_msgs/CooperateCommand`.
struct CooperateCommand
{
  unique_identifier_msgs::msg::UUID uuid;
  Module module;
  Command command;
};

/// `tier4_rtc_msgs/CooperateResponse`.
struct CooperateResponse
{
  unique_identifier_msgs::msg::UUID uuid;
  Module module;
  bool success = false;
};

/// `tier4_rtc_msgs/AutoModeStatus`.
struct AutoModeStatus
{
  Module module;
  bool is_auto_mode = false;
};
}  // namespace tier4_rtc_msgs::msg

namespace tier4_rtc_msgs::srv
{
/// `tier4_rtc_msgs/CooperateCommands`.
struct CooperateCommands
{
  struct Request
  {
    using SharedPtr = std::shared_ptr<Request>;
    builtin_interfaces::msg::Time stamp;
    std::vector<msg::CooperateCommand> commands;
  };
  struct Response
  {
    using SharedPtr = std::shared_ptr<Response>;
    std::vector<msg::CooperateResponse> responses;
  };
};

/// `tier4_rtc_msgs/AutoMode`.
struct AutoMode
{
  struct Request
  {
    using SharedPtr = std::shared_ptr<Request>;
    bool enable = false;
  };
  struct Response
  {
    using SharedPtr = std::shared_ptr<Response>;
    bool success = false;
  };
};
}  // namespace tier4_rtc_msgs::srv

#endif  // COOPERATION__RTC__MESSAGES_HPP_
