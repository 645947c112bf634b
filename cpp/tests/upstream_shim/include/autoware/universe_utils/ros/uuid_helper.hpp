// The UUID helper a test for upstream's RTC interface calls: a random version 4 UUID.
// For `tools/cpp-upstream`; not installed.
#ifndef COOPERATION_UPSTREAM_SHIM__UUID_HELPER_HPP_
#define COOPERATION_UPSTREAM_SHIM__UUID_HELPER_HPP_

#include "cooperation/rtc/messages.hpp"

#include <random>

namespace autoware::universe_utils
{
inline unique_identifier_msgs::msg::UUID generateUUID()
{
  static std::mt19937 random{std::random_device{}()};
  unique_identifier_msgs::msg::UUID uuid;
  for (auto & byte : uuid.uuid) {
    byte = static_cast<uint8_t>(random());
  }
  uuid.uuid[6] = static_cast<uint8_t>((uuid.uuid[6] & 0x0f) | 0x40);
  uuid.uuid[8] = static_cast<uint8_t>((uuid.uuid[8] & 0x3f) | 0x80);
  return uuid;
}
}  // namespace autoware::universe_utils

#endif  // COOPERATION_UPSTREAM_SHIM__UUID_HELPER_HPP_
