// A planning module on the verified core: an intersection module that, each planning cycle,
// asks its RTC interface whether each scene may go, plans, and reports its scenes, as
// behavior_velocity_planner's modules do (`setActivation`, then `sendRTC`). An operator in the
// same process approves a scene through the interface's service. The code a module has today
// compiles unchanged: only the include path and the library differ (docs/cpp.md).
#include "autoware/rtc_interface/rtc_interface.hpp"

#include <cstdio>
#include <map>

using autoware::rtc_interface::Command;
using autoware::rtc_interface::CooperateCommand;
using autoware::rtc_interface::CooperateCommands;
using autoware::rtc_interface::RTCInterface;
using autoware::rtc_interface::State;
using autoware::rtc_interface::UUID;

namespace
{
/// One scene of the module: a stop line it may pass once approved.
struct Scene
{
  UUID uuid;
  double distance;
  bool safe;
  bool activated = false;
};

class IntersectionModule
{
public:
  explicit IntersectionModule(cooperation::rtc::Node * node)
  : node_(node), rtc_(node, "intersection", /*enable_rtc=*/true)
  {
  }

  void add(const Scene & scene) { scenes_.push_back(scene); }

  /// One planning cycle: ask, plan, report.
  void cycle()
  {
    for (auto & scene : scenes_) {  // setActivation
      scene.activated = rtc_.isActivated(scene.uuid);
    }
    for (auto & scene : scenes_) {  // plan: approach the stop line, or pass it
      scene.distance -= scene.activated ? 5.0 : (scene.distance > 5.0 ? 2.0 : 0.0);
    }
    for (const auto & scene : scenes_) {  // sendRTC
      const uint8_t state = (!scene.activated && scene.safe) ? State::WAITING_FOR_EXECUTION
                                                             : State::RUNNING;
      rtc_.updateCooperateStatus(
        scene.uuid, scene.safe, state, scene.distance, scene.distance, node_->now());
    }
    rtc_.removeExpiredCooperateStatus();
    rtc_.publishCooperateStatus(node_->now());
  }

  bool activated(std::size_t i) const { return scenes_.at(i).activated; }

private:
  cooperation::rtc::Node * node_;
  RTCInterface rtc_;
  std::vector<Scene> scenes_;
};

UUID uuid(uint8_t n)
{
  UUID id;
  id.uuid[0] = 0x5c;
  id.uuid[15] = n;
  return id;
}
}  // namespace

int main()
{
  cooperation::rtc::Node node("behavior_velocity_planner");
  IntersectionModule module(&node);
  module.add({uuid(1), 40.0, true});
  module.add({uuid(2), 60.0, false});

  builtin_interfaces::msg::Time now;
  now.sec = 1000;
  for (int cycle = 0; cycle < 5; ++cycle) {
    node.set_now(now);
    module.cycle();
    now.nanosec += 100000000;  // 10 Hz
  }
  std::printf("before approval: scene 1 %s, scene 2 %s\n",
              module.activated(0) ? "goes" : "waits", module.activated(1) ? "goes" : "waits");

  // The operator approves scene 2, which the module judges unsafe: a forced activation.
  CooperateCommands::Request request;
  CooperateCommand approve;
  approve.uuid = uuid(2);
  approve.command.type = Command::ACTIVATE;
  request.commands.push_back(approve);
  const auto reply = node.call<CooperateCommands>("/planning/cooperate_commands/intersection", request);
  std::printf("operator's command: %s\n",
              reply && reply->responses.at(0).success ? "accepted" : "refused");

  node.set_now(now);
  module.cycle();
  module.cycle();
  std::printf("after approval: scene 1 %s, scene 2 %s\n",
              module.activated(0) ? "goes" : "waits", module.activated(1) ? "goes" : "waits");
  const bool as_expected = !module.activated(0) && module.activated(1) && reply &&
                           reply->responses.at(0).success;
  return as_expected ? 0 : 1;
}
