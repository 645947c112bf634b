// What a test written for upstream's RTC interface needs of rclcpp's node, without ROS 2: the
// node is the library's plain node (`cooperation::rtc::Node`), which `RTCInterface` is built on
// when rclcpp is absent. For `tools/cpp-upstream`; not installed.
#ifndef COOPERATION_UPSTREAM_SHIM__RCLCPP__NODE_HPP_
#define COOPERATION_UPSTREAM_SHIM__RCLCPP__NODE_HPP_

#include "cooperation/rtc/node.hpp"

#include <memory>
#include <string>

namespace rclcpp
{
/// Nothing to start or stop without ROS 2.
inline void init(int, const char * const *) {}
inline bool shutdown() { return true; }

class Node : public cooperation::rtc::Node
{
public:
  using SharedPtr = std::shared_ptr<Node>;
  explicit Node(const std::string & name) : cooperation::rtc::Node(name) {}
};
}  // namespace rclcpp

#endif  // COOPERATION_UPSTREAM_SHIM__RCLCPP__NODE_HPP_
