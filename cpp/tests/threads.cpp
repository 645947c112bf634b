// Two planner threads and an operator thread on one node: every report and every accepted
// command lands, none is lost or half-applied (`[COOP-DEV-RACE.1]`); and the node's clock, set
// by one thread while another reads it, reads whole. Run under ThreadSanitizer by `tools/cpp`
// (docs/cpp.md).
#include "check.hpp"

#include <cstdint>
#include <thread>
#include <tuple>

using autoware::rtc_interface::Command;
using autoware::rtc_interface::CooperateCommand;
using autoware::rtc_interface::CooperateCommands;
using autoware::rtc_interface::CooperateStatusArray;
using autoware::rtc_interface::RTCInterface;
using autoware::rtc_interface::State;
using autoware::rtc_interface::UUID;

namespace
{
constexpr unsigned kScenes = 300;
constexpr unsigned kReports = 20;

/// A planner: registers its scenes, then reports each `kReports` times, the distance growing,
/// asking its interface each time, as a planning cycle does.
void plan(RTCInterface & rtc, unsigned base)
{
  for (unsigned report = 0; report < kReports; ++report) {
    for (unsigned i = 0; i < kScenes; ++i) {
      const UUID id = check::uuid(base + i);
      (void)rtc.isActivated(id);
      rtc.updateCooperateStatus(
        id, false, State::WAITING_FOR_EXECUTION, i + report, i + report, check::at(0));
      rtc.removeExpiredCooperateStatus();
    }
  }
}

/// The operator: activates every scene of `name`, one command a request, retrying those not
/// registered yet, until each has been accepted once (or, if some never are, for a bounded
/// number of rounds, which the checks then report). Answers how many were never accepted.
unsigned operate(cooperation::rtc::Node & node, const std::string & name, unsigned base)
{
  std::vector<bool> accepted(kScenes, false);
  unsigned left = kScenes;
  for (unsigned round = 0; left > 0 && round < 100000; ++round) {
    for (unsigned i = 0; i < kScenes; ++i) {
      if (accepted[i]) {
        continue;
      }
      CooperateCommands::Request request;
      CooperateCommand command;
      command.uuid = check::uuid(base + i);
      command.command.type = Command::ACTIVATE;
      request.commands.push_back(command);
      const auto reply = node.call<CooperateCommands>("/planning/cooperate_commands/" + name, request);
      if (reply && reply->responses.size() == 1 && reply->responses[0].success) {
        accepted[i] = true;
        --left;
      }
    }
  }
  return left;
}

/// The node's clock set by one thread (the planner's) while another reads it (an interface's
/// update): every reading is one time that was set, its seconds and nanoseconds together, and
/// never earlier than a reading before it.
void a_clock_read_while_set_shows_one_time_set()
{
  constexpr uint32_t kTimes = 200000;
  cooperation::rtc::Node node("clock");
  std::thread planner([&] {
    for (uint32_t k = 1; k <= kTimes; ++k) {
      node.set_now(check::at(static_cast<int32_t>(k), k * 7));
    }
  });
  bool whole = true;
  bool forward = true;
  int32_t last = 0;
  for (uint32_t read = 0; read < kTimes; ++read) {
    const auto now = node.now();
    whole = whole && now.nanosec == static_cast<uint32_t>(now.sec) * 7;
    forward = forward && now.sec >= last;
    last = now.sec;
  }
  planner.join();
  CHECK(whole, "every reading of the clock is one time that was set");
  CHECK(forward, "no reading is earlier than one before it");
  CHECK(node.now().sec == static_cast<int32_t>(kTimes), "the last time set is read");
}
}  // namespace

int main()
{
  cooperation::rtc::Node node("planner");
  node.set_now(check::at(50));
  check::Log log(node);
  // 300 scenes an interface, past the nodes' default quota of 215: this core has none.
  const auto core = cooperation::rtc::core_of(&node, 0);
  RTCInterface intersection(&node, "intersection", true);
  RTCInterface crosswalk(&node, "crosswalk", true);
  {
    std::thread a([&] { plan(intersection, 0); });
    std::thread b([&] { plan(crosswalk, 10000); });
    unsigned never = 0;
    std::thread op([&] {
      never = operate(node, "intersection", 0) + operate(node, "crosswalk", 10000);
    });
    a.join();
    b.join();
    op.join();
    CHECK(never == 0, "every command was accepted once its scene was registered");
  }
  CHECK(!log.warned("update refused"), "no report was refused");
  for (const auto & [rtc, name, base] :
       {std::tuple<RTCInterface *, std::string, unsigned>{&intersection, "intersection", 0},
        {&crosswalk, "crosswalk", 10000}}) {
    rtc->publishCooperateStatus(check::at(51));
    const auto array = node.latest<CooperateStatusArray>("/planning/cooperate_status/" + name);
    CHECK(array && array->statuses.size() == kScenes, name + ": every scene registered once");
    bool last_reports = true;
    bool activated = true;
    for (unsigned i = 0; array && i < array->statuses.size(); ++i) {
      const auto & status = array->statuses[i];
      last_reports = last_reports && status.start_distance == float(i + kReports - 1);
      activated = activated && status.command_status.type == Command::ACTIVATE &&
                  rtc->isActivated(check::uuid(base + i));
    }
    CHECK(last_reports, name + ": each scene shows its planner's last report");
    CHECK(activated, name + ": each scene shows the operator's accepted command");
  }
  a_clock_read_while_set_shows_one_time_set();
  return check::report("threads");
}
