// Upstream's unit test of the RTC interface (`test_rtc_interface.cpp`: one test, twelve steps,
// six answers after each), replayed call for call through the C++ class. The steps are those of
// autowarefoundation/autoware.universe 0.43.0 (commit b8ce82e375, 2025-03-21), where the test
// was added by PR #9202. Each answer is
// asserted against upstream's expected value; where this library answers differently, the
// assertion states this library's value and names the deviation of `spec/cooperation.md`
// section 9 that explains it, and the test checks that the spec has that deviation. An answer
// that differs from upstream's without a tag fails.
#include "check.hpp"

#include <fstream>
#include <set>
#include <sstream>

using autoware::rtc_interface::Command;
using autoware::rtc_interface::CooperateCommands;
using autoware::rtc_interface::RTCInterface;
using autoware::rtc_interface::State;
using autoware::rtc_interface::UUID;

namespace
{
/// Upstream's fixture names its interface `TestRTC`, which no binding has here
/// ([COOP-DEV-INTERFACE-NAME.1]); a bound name with one core module stands in for it.
const char * const kName = "lane_change_left";

/// The six answers upstream checks: registered, activated, force-activated, force-deactivated,
/// RTC-enabled, terminated.
struct Six
{
  bool reg, act, fact, fdeact, rtc, term;
};

std::set<std::string> & tags_used()
{
  static std::set<std::string> tags;
  return tags;
}

/// Asserts each answer equal to upstream's, or to `here` where `tag` names why it differs.
void expect(
  int step, const RTCInterface & rtc, const UUID & id, Six upstream, Six here,
  const std::string & tag = "")
{
  const Six got{rtc.isRegistered(id),       rtc.isActivated(id),  rtc.isForceActivated(id),
                rtc.isForceDeactivated(id), rtc.isRTCEnabled(id), rtc.isTerminated(id)};
  const char * names[] = {"registered", "activated", "force-activated", "force-deactivated",
                          "RTC-enabled", "terminated"};
  const bool up[] = {upstream.reg, upstream.act, upstream.fact, upstream.fdeact, upstream.rtc,
                     upstream.term};
  const bool want[] = {here.reg, here.act, here.fact, here.fdeact, here.rtc, here.term};
  const bool is[] = {got.reg, got.act, got.fact, got.fdeact, got.rtc, got.term};
  for (int i = 0; i < 6; ++i) {
    const std::string where = "step " + std::to_string(step) + " " + names[i];
    if (up[i] == want[i]) {
      CHECK(is[i] == up[i], where + ": as upstream");
    } else {
      CHECK(!tag.empty(), where + ": differs from upstream with no deviation named");
      CHECK(is[i] == want[i], where + ": not upstream's " + (up[i] ? "true" : "false") + " " + tag);
      tags_used().insert(tag);
    }
  }
}

void report(
  RTCInterface & rtc, const UUID & id, bool safe, uint8_t state, bool requested = false)
{
  rtc.updateCooperateStatus(id, safe, state, 10.0, 100.0, check::at(0), requested);
}

/// The private `updateCooperateCommandStatus` upstream's test calls: here the interface's
/// CooperateCommands service. Answers whether every response succeeded.
bool command(cooperation::rtc::Node & node, const UUID & id, uint8_t type)
{
  CooperateCommands::Request request;
  autoware::rtc_interface::CooperateCommand command;
  command.uuid = id;
  command.command.type = type;
  request.commands.push_back(command);
  const auto response =
    node.call<CooperateCommands>(std::string("/planning/cooperate_commands/") + kName, request);
  bool all = response.has_value() && !response->responses.empty();
  for (const auto & r : response ? response->responses : decltype(response->responses){}) {
    all = all && r.success;
  }
  return all;
}

/// Every tag the test used is a deviation heading of the spec.
void tags_are_in_the_spec()
{
  std::ifstream file(COOPERATION_SPEC);
  std::stringstream text;
  text << file.rdbuf();
  CHECK(!text.str().empty(), std::string("the spec is readable at ") + COOPERATION_SPEC);
  for (const auto & tag : tags_used()) {
    for (std::size_t at = 0; (at = tag.find('[', at)) != std::string::npos; ++at) {
      const auto one = tag.substr(at, tag.find(']', at) - at + 1);
      CHECK(
        text.str().find("#### " + one) != std::string::npos, one + " is a deviation of spec §9");
    }
  }
}
}  // namespace

int main()
{
  cooperation::rtc::Node node("test_rtc");
  check::Log log(node);
  const bool enable_rtc = false;
  RTCInterface rtc(&node, kName, enable_rtc);
  CHECK(rtc.core().bound().ok, "the interface is bound");

  // Upstream uses one UUID throughout and registers it again after each removal or clear; an
  // identifier never comes back here once retired ([COOP-DEV-ID-REUSE.1]), so each
  // re-registration uses a fresh one.
  const UUID first = check::uuid(1);

  // Step 1. No registered UUID. Upstream answers RTC-enabled and terminated with its auto-mode
  // flag (true); here there is no answer, which the C++ bool says as false.
  expect(1, rtc, first, {false, false, false, false, true, true},
         {false, false, false, false, false, false}, "[COOP-DEV-UNKNOWN-QUERY.1]");

  // Step 2. Register waiting, safe: auto mode follows `safe`.
  report(rtc, first, true, State::WAITING_FOR_EXECUTION);
  expect(2, rtc, first, {true, true, false, false, false, false},
         {true, true, false, false, false, false});

  // Step 3. Remove. Upstream checks only registered; its other answers are those of an unknown
  // UUID (its auto-mode flag for RTC-enabled and terminated).
  rtc.removeCooperateStatus(first);
  expect(3, rtc, first, {false, false, false, false, true, true},
         {false, false, false, false, false, false}, "[COOP-DEV-UNKNOWN-QUERY.1]");

  // Step 4. Register the same UUID with FAILED. Upstream registers it again, stored waiting.
  // Here the removed identifier is refused, with a warning ...
  report(rtc, first, true, State::FAILED);
  CHECK(log.warned("retired"), "step 4: the refusal is logged [COOP-DEV-SILENT-DROP.1]");
  expect(4, rtc, first, {true, true, false, false, false, false},
         {false, false, false, false, false, false}, "[COOP-DEV-ID-REUSE.1]");
  // ... and a fresh identifier reported FAILED registers and fails in one step: it retires at
  // once, terminated.
  const UUID second = check::uuid(2);
  report(rtc, second, true, State::FAILED);
  expect(4, rtc, second, {true, true, false, false, false, false},
         {false, false, false, false, false, true},
         "[COOP-DEV-REGISTER-PHASE.1] [COOP-DEV-TERMINAL.1]");

  // Step 5. Running, unsafe, then an ACTIVATE command: the operator activated what the module
  // judges unsafe. A fresh identifier registers and runs in one step.
  const UUID third = check::uuid(3);
  report(rtc, third, false, State::RUNNING);
  CHECK(command(node, third, Command::ACTIVATE), "step 5: the command applies");
  expect(5, rtc, third, {true, true, true, false, true, false},
         {true, true, true, false, true, false});
  // Upstream's own path to step 5: its scene was stored waiting at step 4, then reported
  // running. A fresh identifier registered waiting takes the same path here.
  const UUID waited = check::uuid(6);
  report(rtc, waited, true, State::WAITING_FOR_EXECUTION);
  report(rtc, waited, false, State::RUNNING);
  CHECK(command(node, waited, Command::ACTIVATE), "step 5 (from waiting): the command applies");
  expect(5, rtc, waited, {true, true, true, false, true, false},
         {true, true, true, false, true, false});

  // Step 6. SUCCEEDED. Upstream keeps the scene listed; here it retires at once, and is
  // terminated as upstream.
  report(rtc, third, false, State::SUCCEEDED);
  expect(6, rtc, third, {true, false, false, false, true, true},
         {false, false, false, false, false, true},
         "[COOP-DEV-TERMINAL.1] [COOP-DEV-UNKNOWN-QUERY.1]");

  // Step 7. Clear. Upstream: not registered, and its stored commands are empty. Nothing is
  // ever stored here: a command for the finished scene, or one not registered yet, is refused.
  rtc.clearCooperateStatus();
  CHECK(!rtc.isRegistered(third), "step 7 registered: as upstream");
  CHECK(!command(node, third, Command::ACTIVATE), "step 7: [COOP-DEV-STORED-COMMANDS.1]");
  CHECK(!command(node, check::uuid(4), Command::ACTIVATE), "step 7: [COOP-DEV-STORED-COMMANDS.1]");
  CHECK(log.warned("commands refused"), "step 7: the refusals are logged");

  // Step 8. Register waiting (safe), run, DEACTIVATE: the operator stopped a running manoeuvre
  // the module judges safe.
  const UUID fourth = check::uuid(4);
  report(rtc, fourth, true, State::WAITING_FOR_EXECUTION);
  report(rtc, fourth, true, State::RUNNING);
  CHECK(command(node, fourth, Command::DEACTIVATE), "step 8: the command applies");
  expect(8, rtc, fourth, {true, false, false, true, true, false},
         {true, false, false, true, true, false});

  // Step 9. ABORTING.
  report(rtc, fourth, true, State::ABORTING);
  expect(9, rtc, fourth, {true, false, false, false, true, false},
         {true, false, false, false, true, false});

  // Step 10. FAILED: upstream keeps it listed; here it retires, terminated as upstream.
  report(rtc, fourth, true, State::FAILED);
  expect(10, rtc, fourth, {true, false, false, false, true, true},
         {false, false, false, false, false, true},
         "[COOP-DEV-TERMINAL.1] [COOP-DEV-UNKNOWN-QUERY.1]");

  // Step 11. Clear; register waiting with `requested`, run with `requested`: a requested scene
  // waits for the operator although auto mode is on and the module judges it safe.
  rtc.clearCooperateStatus();
  const UUID fifth = check::uuid(5);
  report(rtc, fifth, true, State::WAITING_FOR_EXECUTION, true);
  report(rtc, fifth, true, State::RUNNING, true);
  expect(11, rtc, fifth, {true, false, false, false, false, false},
         {true, false, false, false, false, false});

  // Step 12. ACTIVATE: activating a requested scene counts as forced.
  CHECK(command(node, fifth, Command::ACTIVATE), "step 12: the command applies");
  expect(12, rtc, fifth, {true, true, true, false, true, false},
         {true, true, true, false, true, false});

  tags_are_in_the_spec();
  return check::report("upstream");
}
