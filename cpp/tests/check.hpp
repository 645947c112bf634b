// The tests' one assertion: it counts, says what failed and where, and the test's exit status
// and last line (`N passed, N failed`) report the count.
#ifndef COOPERATION_TESTS_CHECK_HPP_
#define COOPERATION_TESTS_CHECK_HPP_

#include "autoware/rtc_interface/rtc_interface.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace check
{
inline int & passed()
{
  static int count = 0;
  return count;
}
inline int & failed()
{
  static int count = 0;
  return count;
}
inline void that(bool condition, const std::string & what, const char * file, int line)
{
  if (condition) {
    ++passed();
  } else {
    ++failed();
    std::printf("FAILED %s:%d: %s\n", file, line, what.c_str());
  }
}
inline int report(const char * test)
{
  std::printf("%s: %d passed, %d failed\n", test, passed(), failed());
  return failed() == 0 && passed() > 0 ? 0 : 1;
}

/// A UUID whose last bytes are `n`.
inline unique_identifier_msgs::msg::UUID uuid(unsigned n)
{
  unique_identifier_msgs::msg::UUID id;
  for (int i = 0; i < 4; ++i) {
    id.uuid[15 - i] = static_cast<uint8_t>(n >> (8 * i));
  }
  id.uuid[0] = 0xc0;
  return id;
}

inline builtin_interfaces::msg::Time at(int32_t sec, uint32_t nanosec = 0)
{
  builtin_interfaces::msg::Time time;
  time.sec = sec;
  time.nanosec = nanosec;
  return time;
}

/// Collects a node's log lines.
struct Log
{
  std::vector<std::pair<cooperation::rtc::Logger::Level, std::string>> lines;
  explicit Log(cooperation::rtc::Node & node)
  {
    node.get_logger().set_sink(
      [this](cooperation::rtc::Logger::Level level, const std::string &, const std::string & text) {
        lines.emplace_back(level, text);
      });
  }
  /// Whether a warning containing `part` was logged; forgets the lines.
  bool warned(const std::string & part)
  {
    bool found = false;
    for (const auto & [level, text] : lines) {
      found = found || (level == cooperation::rtc::Logger::Level::Warn &&
                        text.find(part) != std::string::npos);
    }
    lines.clear();
    return found;
  }
};
}  // namespace check

#define CHECK(condition, what) ::check::that((condition), (what), __FILE__, __LINE__)

#endif  // COOPERATION_TESTS_CHECK_HPP_
