// rclcpp's time as a test for upstream's RTC interface uses it: built from seconds and
// nanoseconds, and taken where the interface takes the node's time (`builtin_interfaces`).
// For `tools/cpp-upstream`; not installed.
#ifndef COOPERATION_UPSTREAM_SHIM__RCLCPP__TIME_HPP_
#define COOPERATION_UPSTREAM_SHIM__RCLCPP__TIME_HPP_

#include "cooperation/rtc/messages.hpp"

#include <cstdint>

namespace rclcpp
{
class Time
{
public:
  Time(int32_t seconds, uint32_t nanoseconds)
  {
    time_.sec = seconds;
    time_.nanosec = nanoseconds;
  }
  operator builtin_interfaces::msg::Time() const { return time_; }  // NOLINT: as rclcpp's

private:
  builtin_interfaces::msg::Time time_;
};
}  // namespace rclcpp

#endif  // COOPERATION_UPSTREAM_SHIM__RCLCPP__TIME_HPP_
