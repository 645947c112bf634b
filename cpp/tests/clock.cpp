// The node's clock as planning modules drive it: each cycle every module reports its scenes and
// then calls removeExpiredCooperateStatus, one module after another, and the clock may jump
// (a bag seek, the first /clock message, a stalled planner) or go back (a bag played again).
// No jump retires a scene its module still reports ([COOP-ENGINE-STEP.1]); a report or a
// command is made at the clock's now whichever call comes first ([COOP-ENGINE-TIME.1]); a scene
// no longer reported still expires, after a clock that went back too. Run under
// AddressSanitizer too by tools/cpp.
#include "check.hpp"

#include <cstdint>
#include <string>
#include <vector>

using autoware::rtc_interface::Command;
using autoware::rtc_interface::CooperateCommands;
using autoware::rtc_interface::RTCInterface;
using autoware::rtc_interface::State;
using cooperation::rtc::Node;
using unique_identifier_msgs::msg::UUID;

namespace
{
/// A planning module: its interface and the scene it reports each cycle.
struct Module
{
  RTCInterface & rtc;
  UUID scene;
};

/// The time `ms` milliseconds after second `base`.
builtin_interfaces::msg::Time after(int32_t base, int64_t ms)
{
  return check::at(
    base + static_cast<int32_t>(ms / 1000), static_cast<uint32_t>(ms % 1000) * 1000000U);
}

/// One planning cycle at `time`: each module reports its scene, then tells the time, in turn
/// (behavior_path_planner's and behavior_velocity_planner's order). `expiry_first` calls
/// removeExpiredCooperateStatus before the report instead.
void cycle(
  Node & node, const builtin_interfaces::msg::Time & time, std::vector<Module> & modules,
  bool expiry_first = false)
{
  node.set_now(time);
  for (auto & module : modules) {
    if (expiry_first) {
      module.rtc.removeExpiredCooperateStatus();
    }
    module.rtc.updateCooperateStatus(
      module.scene, true, State::WAITING_FOR_EXECUTION, 10.0, 20.0, time);
    if (!expiry_first) {
      module.rtc.removeExpiredCooperateStatus();
    }
  }
}

bool all_registered(const std::vector<Module> & modules)
{
  bool all = true;
  for (const auto & module : modules) {
    all = all && module.rtc.isRegistered(module.scene);
  }
  return all;
}

void a_jump_retires_no_scene_still_reported(bool expiry_first)
{
  const std::string order = expiry_first ? " (expiry first)" : " (report first)";
  Node node("planner");
  check::Log log(node);
  RTCInterface crosswalk(&node, "crosswalk", true);
  RTCInterface blind_spot(&node, "blind_spot", true);
  std::vector<Module> modules{{crosswalk, check::uuid(1)}, {blind_spot, check::uuid(2)}};
  // Sim time before the first /clock message is 0; then the clock reads the epoch.
  cycle(node, check::at(0), modules, expiry_first);
  cycle(node, after(0, 100), modules, expiry_first);
  cycle(node, check::at(1700000000), modules, expiry_first);
  CHECK(all_registered(modules), "the first /clock retires nothing still reported" + order);
  // A bag seek 20 s ahead, then cycles on.
  cycle(node, check::at(1700000020), modules, expiry_first);
  cycle(node, after(1700000020, 100), modules, expiry_first);
  CHECK(all_registered(modules), "a seek ahead retires nothing still reported" + order);
  // A planner stalled for 15 s.
  cycle(node, after(1700000035, 100), modules, expiry_first);
  CHECK(all_registered(modules), "a stall retires nothing still reported" + order);
  // The bag played again from its start: the clock went back.
  cycle(node, check::at(1699999990), modules, expiry_first);
  cycle(node, after(1699999990, 100), modules, expiry_first);
  CHECK(all_registered(modules), "a clock that went back retires nothing" + order);
  CHECK(!log.warned("refused"), "no report was refused" + order);
  for (const auto & line : log.lines) {
    CHECK(line.second.find("expired") == std::string::npos, "nothing expired: " + line.second);
  }
}

void a_scene_no_longer_reported_still_expires()
{
  Node node("planner");
  check::Log log(node);
  RTCInterface crosswalk(&node, "crosswalk", true);
  RTCInterface blind_spot(&node, "blind_spot", true);
  std::vector<Module> both{{crosswalk, check::uuid(3)}, {blind_spot, check::uuid(4)}};
  cycle(node, check::at(100), both);
  // The blind spot module stops reporting its scene; a seek 60 s ahead counts 1 s.
  std::vector<Module> crossing_only{{crosswalk, check::uuid(3)}};
  cycle(node, check::at(160), crossing_only);
  CHECK(blind_spot.isRegistered(check::uuid(4)), "a jump counts the step limit, not 60 s");
  int64_t ms = 0;
  while (blind_spot.isRegistered(check::uuid(4)) && ms < 20000) {
    ms += 100;
    cycle(node, after(160, ms), crossing_only);
  }
  // 1 s counted for the seek, then 9 s and a cycle of cycles.
  CHECK(ms == 9100, "expired after its time to live in the core's time, at " + std::to_string(ms));
  CHECK(crosswalk.isRegistered(check::uuid(3)), "the scene still reported lives");
  bool logged = false;
  for (const auto & line : log.lines) {
    logged = logged || line.second.find("expired") != std::string::npos;
  }
  CHECK(logged, "the expiry is logged");
}

void a_report_is_made_at_the_clocks_now()
{
  Node node("planner");
  RTCInterface crosswalk(&node, "crosswalk", true);
  const UUID id = check::uuid(5);
  node.set_now(check::at(10));
  crosswalk.removeExpiredCooperateStatus();
  // Reported 900 ms after the core was last told, before any call tells it the time.
  node.set_now(after(10, 900));
  crosswalk.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 1.0, 1.0, check::at(0));
  // Half-second cycles, each step within the step limit, to 20.9 s: 10 s after the report.
  for (int64_t ms = 1000; ms <= 10900; ms = ms == 10500 ? 10900 : ms + 500) {
    node.set_now(after(10, ms));
    crosswalk.removeExpiredCooperateStatus();
  }
  CHECK(crosswalk.isRegistered(id), "the scene lives its time to live from its report's time");
  node.set_now(check::at(21));
  crosswalk.removeExpiredCooperateStatus();
  CHECK(!crosswalk.isRegistered(id), "and expires after it");
}
void a_clock_that_went_back_still_ages_scenes()
{
  Node node("planner");
  RTCInterface crosswalk(&node, "crosswalk", true);
  RTCInterface blind_spot(&node, "blind_spot", true);
  std::vector<Module> both{{crosswalk, check::uuid(6)}, {blind_spot, check::uuid(7)}};
  cycle(node, check::at(100), both);
  // The bag is played again from 50 s; the blind spot module no longer reports its scene.
  std::vector<Module> crossing_only{{crosswalk, check::uuid(6)}};
  int64_t ms = 0;
  do {
    cycle(node, after(50, ms), crossing_only);
    ms += 100;
  } while (blind_spot.isRegistered(check::uuid(7)) && ms < 60000);
  CHECK(ms == 10200, "time counts on from the earlier reading: expired at " + std::to_string(ms));
  CHECK(crosswalk.isRegistered(check::uuid(6)), "the scene still reported lives");
}

void a_command_is_made_at_the_clocks_now()
{
  Node node("planner");
  check::Log log(node);
  RTCInterface crosswalk(&node, "crosswalk", true);
  const UUID id = check::uuid(8);
  node.set_now(check::at(10));
  crosswalk.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 1.0, 1.0, check::at(0));
  for (int32_t second = 11; second <= 20; ++second) {
    node.set_now(check::at(second));
    crosswalk.removeExpiredCooperateStatus();
  }
  CHECK(crosswalk.isRegistered(id), "within its time to live");
  // 10.9 s after the report, with no call since the last second: the command tells the time.
  node.set_now(after(20, 900));
  CooperateCommands::Request request;
  autoware::rtc_interface::CooperateCommand command;
  command.uuid = id;
  command.command.type = Command::ACTIVATE;
  request.commands.push_back(command);
  const auto response = node.call<CooperateCommands>("/planning/cooperate_commands/crosswalk", request);
  CHECK(
    response && response->responses.size() == 1 && !response->responses[0].success,
    "a command after the scene's time to live is refused");
  CHECK(!crosswalk.isRegistered(id), "the scene expired by the command's time");
  bool logged = false;
  for (const auto & line : log.lines) {
    logged = logged || line.second.find(" expired") != std::string::npos;
  }
  CHECK(logged, "the expiry the command's time brought is logged");
}
}  // namespace

int main()
{
  a_jump_retires_no_scene_still_reported(false);
  a_jump_retires_no_scene_still_reported(true);
  a_scene_no_longer_reported_still_expires();
  a_report_is_made_at_the_clocks_now();
  a_clock_that_went_back_still_ages_scenes();
  a_command_is_made_at_the_clocks_now();
  return check::report("clock");
}
