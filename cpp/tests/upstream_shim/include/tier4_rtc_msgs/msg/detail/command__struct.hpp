// The generated header of `tier4_rtc_msgs/msg/Command`: without ROS 2, the library's plain
// message structs. For `tools/cpp-upstream`; not installed.
#ifndef COOPERATION_UPSTREAM_SHIM__COMMAND__STRUCT_HPP_
#define COOPERATION_UPSTREAM_SHIM__COMMAND__STRUCT_HPP_

#include "cooperation/rtc/messages.hpp"

#endif  // COOPERATION_UPSTREAM_SHIM__COMMAND__STRUCT_HPP_
