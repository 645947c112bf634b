// A planning-module plugin as Autoware builds one: a shared object linking the shared RTC
// library, loaded by its node with dlopen (as pluginlib and class_loader load plugins: lazily,
// symbols local). Built twice, as two plugins of one node (tests/plugins/host.cpp).
#include "autoware/rtc_interface/rtc_interface.hpp"

#include <memory>
#include <string>
#include <vector>

namespace
{
std::vector<std::unique_ptr<autoware::rtc_interface::RTCInterface>> & interfaces()
{
  static std::vector<std::unique_ptr<autoware::rtc_interface::RTCInterface>> list;
  return list;
}
}  // namespace

/// Makes the interface `name` on `node` and reports the scene whose UUID's bytes are all
/// `byte`; whether the interface holds it then.
extern "C" bool plugin_report(cooperation::rtc::Node * node, const char * name, unsigned char byte)
{
  auto rtc = std::make_unique<autoware::rtc_interface::RTCInterface>(node, name, true);
  unique_identifier_msgs::msg::UUID id;
  id.uuid.fill(byte);
  builtin_interfaces::msg::Time stamp;
  stamp.sec = 1;
  rtc->updateCooperateStatus(
    id, true, autoware::rtc_interface::State::WAITING_FOR_EXECUTION, 10.0, 10.0, stamp);
  const bool registered = rtc->isRegistered(id);
  interfaces().push_back(std::move(rtc));
  return registered;
}

/// Drops the plugin's interfaces (before its node goes).
extern "C" void plugin_unload() { interfaces().clear(); }
