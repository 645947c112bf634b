// The C++ class beyond upstream's own test: its topics, services and timer, a node's interfaces
// sharing one core, time, names with no binding, hostile arguments, and the deviations a module
// meets first. Each refusal is asserted to change nothing and to be logged.
#include "check.hpp"

using autoware::rtc_interface::AutoMode;
using autoware::rtc_interface::AutoModeStatus;
using autoware::rtc_interface::Command;
using autoware::rtc_interface::CooperateCommand;
using autoware::rtc_interface::CooperateCommands;
using autoware::rtc_interface::CooperateStatusArray;
using autoware::rtc_interface::Module;
using autoware::rtc_interface::RTCInterface;
using autoware::rtc_interface::State;
using autoware::rtc_interface::UUID;
using cooperation::rtc::Node;

namespace
{
CooperateCommands::Request commands(std::initializer_list<std::pair<UUID, uint8_t>> list)
{
  CooperateCommands::Request request;
  for (const auto & [id, type] : list) {
    CooperateCommand command;
    command.uuid = id;
    command.command.type = type;
    request.commands.push_back(command);
  }
  return request;
}

void topics_services_and_timer()
{
  Node node("planner");
  check::Log log(node);
  RTCInterface rtc(&node, "intersection", true);
  const UUID id = check::uuid(1);
  rtc.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 12.5, 12.5, check::at(0));
  rtc.publishCooperateStatus(check::at(100, 5));
  const auto array = node.latest<CooperateStatusArray>("/planning/cooperate_status/intersection");
  CHECK(array.has_value(), "statuses are published on upstream's topic");
  CHECK(array && array->stamp.sec == 100 && array->stamp.nanosec == 5, "the array's stamp");
  CHECK(array && array->statuses.size() == 1, "one status");
  if (array && array->statuses.size() == 1) {
    const auto & status = array->statuses[0];
    CHECK(status.uuid.uuid == id.uuid, "its uuid");
    CHECK(status.module.type == Module::INTERSECTION, "its module type");
    CHECK(status.safe && !status.requested, "safe, not requested");
    CHECK(status.command_status.type == Command::DEACTIVATE, "no command: DEACTIVATE [COOP-DEV-NONE.1]");
    CHECK(status.state.type == State::WAITING_FOR_EXECUTION, "waiting");
    CHECK(!status.auto_mode, "enable_rtc: not auto mode");
    CHECK(status.start_distance == 12.5F && status.finish_distance == 12.5F, "its distances");
    CHECK(status.stamp.sec == 100 && status.stamp.nanosec == 5, "reported just now");
  }
  CHECK(!rtc.isActivated(id), "required policy: waits for the operator");

  node.fire_timers();
  const auto mode = node.latest<AutoModeStatus>("/planning/auto_mode_status/intersection");
  CHECK(mode && mode->module.type == Module::INTERSECTION && !mode->is_auto_mode,
        "the timer publishes the auto-mode status");

  AutoMode::Request enable;
  enable.enable = true;
  const auto switched = node.call<AutoMode>("/planning/enable_auto_mode/intersection", enable);
  CHECK(switched && switched->success, "the auto-mode service answers success");
  CHECK(rtc.isActivated(id), "auto mode: follows the module, which judges it safe");
  node.fire_timers();
  const auto on = node.latest<AutoModeStatus>("/planning/auto_mode_status/intersection");
  CHECK(on && on->is_auto_mode, "the auto-mode status follows");

  const auto reply = node.call<CooperateCommands>(
    "/planning/cooperate_commands/intersection", commands({{id, Command::DEACTIVATE}}));
  CHECK(reply && reply->responses.size() == 1 && reply->responses[0].success, "a command applies");
  CHECK(!rtc.isActivated(id), "the operator's decision wins over auto mode");
  node.call<AutoMode>("/planning/enable_auto_mode/intersection", enable);
  CHECK(!rtc.isActivated(id), "switching auto mode keeps it [COOP-DEV-POLICY-CLOBBER.1]");

  const auto duplicate = node.call<CooperateCommands>(
    "/planning/cooperate_commands/intersection",
    commands({{id, Command::ACTIVATE}, {id, Command::DEACTIVATE}}));
  CHECK(duplicate && duplicate->responses.size() == 2, "every command is answered");
  CHECK(duplicate && !duplicate->responses[0].success && !duplicate->responses[1].success,
        "a batch naming a scene twice is refused whole [COOP-DEV-DUPLICATE.1]");
  CHECK(log.warned("commands refused"), "and logged");
  CHECK(!rtc.isActivated(id), "nothing changed");

  rtc.lockCommandUpdate();
  node.call<CooperateCommands>(
    "/planning/cooperate_commands/intersection", commands({{id, Command::ACTIVATE}}));
  CHECK(rtc.isActivated(id), "a command applies at once, locked or not [COOP-DEV-STORED-COMMANDS.1]");
  rtc.unlockCommandUpdate();
  CHECK(rtc.isActivated(id), "unlocking re-applies nothing");

  rtc.print();
  CHECK(log.lines.size() == 1 && log.lines[0].second.find("command : ACTIVATE") != std::string::npos,
        "print logs each scene");
}

void one_core_per_node()
{
  Node node("planner");
  check::Log log(node);
  RTCInterface left(&node, "lane_change_left", true);
  RTCInterface right(&node, "lane_change_right", true);
  const UUID id = check::uuid(7);
  left.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 1, 50, check::at(0));
  CHECK(left.isRegistered(id) && !right.isRegistered(id), "a scene is its interface's");
  right.updateCooperateStatus(id, true, State::RUNNING, 1, 50, check::at(0));
  CHECK(log.warned("update refused"), "another interface's scene is refused [COOP-DEV-ID-REUSE.1]");
  const auto foreign = node.call<CooperateCommands>(
    "/planning/cooperate_commands/lane_change_right", commands({{id, Command::ACTIVATE}}));
  CHECK(foreign && !foreign->responses[0].success && log.warned("commands refused"),
        "a command for another interface's scene is refused");
  AutoMode::Request enable;
  enable.enable = true;
  node.call<AutoMode>("/planning/enable_auto_mode/lane_change_right", enable);
  CHECK(left.isActivated(id), "lane change left and right share one policy [COOP-DEV-AUTO-MODE-KEY.1]");

  Node other("other");
  RTCInterface elsewhere(&other, "lane_change_left", true);
  CHECK(!elsewhere.isRegistered(id), "another node has a core of its own");
}

void time_passes_once_a_cycle()
{
  Node node("planner");
  check::Log log(node);
  RTCInterface a(&node, "crosswalk", true);
  RTCInterface b(&node, "blind_spot", true);
  const UUID id = check::uuid(9);
  node.set_now(check::at(1000));
  a.removeExpiredCooperateStatus();  // The first reading is the core's time 0.
  a.updateCooperateStatus(id, false, State::WAITING_FOR_EXECUTION, 3, 3, check::at(1000));
  // Cycles a second apart (a longer step counts the step limit, [COOP-ENGINE-STEP.1]).
  for (int32_t second = 1001; second <= 1006; ++second) {
    node.set_now(check::at(second));
    for (int i = 0; i < 3; ++i) {
      a.removeExpiredCooperateStatus();
      b.removeExpiredCooperateStatus();
    }
  }
  CHECK(a.isRegistered(id), "six seconds pass once, however many interfaces tell the core");
  for (int32_t second = 1007; second <= 1011; ++second) {
    node.set_now(check::at(second));
    b.removeExpiredCooperateStatus();
  }
  CHECK(!a.isRegistered(id), "eleven seconds unreported: expired");
  bool logged = false;
  for (const auto & line : log.lines) {
    logged = logged || line.second.find("expired") != std::string::npos;
  }
  CHECK(logged, "the expiry is logged [COOP-DEV-EXPIRY.1]");
  node.set_now(check::at(900));
  a.removeExpiredCooperateStatus();
  const UUID later = check::uuid(10);
  a.updateCooperateStatus(later, false, State::WAITING_FOR_EXECUTION, 3, 3, check::at(0));
  node.set_now(check::at(1012));
  a.removeExpiredCooperateStatus();
  CHECK(a.isRegistered(later), "a clock that went back makes no time pass twice");
}

void names_without_a_binding()
{
  Node node("planner");
  check::Log log(node);
  RTCInterface unknown(&node, "TestRTC", false);
  CHECK(!unknown.core().bound().ok, "an unbound name is not bound");
  CHECK(log.warned("TestRTC"), "and the construction says so [COOP-DEV-INTERFACE-NAME.1]");
  const UUID id = check::uuid(1);
  unknown.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 1, 1, check::at(0));
  CHECK(log.warned("update refused"), "a report is refused and logged");
  CHECK(!unknown.isRegistered(id) && !unknown.isActivated(id) && !unknown.isRTCEnabled(id) &&
          !unknown.isTerminated(id),
        "every query answers false");
  unknown.publishCooperateStatus(check::at(1));
  const auto array = node.latest<CooperateStatusArray>("/planning/cooperate_status/TestRTC");
  CHECK(array && array->statuses.empty(), "it publishes no scene");
  const auto reply = node.call<CooperateCommands>(
    "/planning/cooperate_commands/TestRTC", commands({{id, Command::ACTIVATE}}));
  CHECK(reply && reply->responses.size() == 1 && !reply->responses[0].success,
        "its command service answers every command, unsuccessfully");
  unknown.removeCooperateStatus(id);
  unknown.clearCooperateStatus();
  unknown.print();
  RTCInterface garbled(&node, std::string("lane\xff\xfe"), true);
  CHECK(!garbled.core().bound().ok && log.warned("UTF-8"), "a name that is not UTF-8 is refused, not thrown");
}

void hostile_arguments()
{
  Node node("planner");
  check::Log log(node);
  RTCInterface rtc(&node, "intersection", false);
  const UUID id = check::uuid(3);
  rtc.updateCooperateStatus(id, true, 7, 1, 1, check::at(0));
  CHECK(log.warned("state.type is 7") && !rtc.isRegistered(id),
        "an undefined state is refused, naming the field [COOP-DEV-CONSTANTS.1]");
  rtc.updateCooperateStatus(id, true, State::ABORTING, 1, 1, check::at(0));
  CHECK(log.warned("update refused") && !rtc.isRegistered(id),
        "a scene cannot start aborting [COOP-DEV-REGISTER-PHASE.1]");
  // The core takes every distance as it is, NaN and infinities too (they sort after every
  // number); a double beyond float's range is an infinity.
  rtc.updateCooperateStatus(check::uuid(5), true, State::WAITING_FOR_EXECUTION, std::nan(""), 1, check::at(0));
  rtc.updateCooperateStatus(check::uuid(6), true, State::WAITING_FOR_EXECUTION, 1e300, 1, check::at(0));
  rtc.publishCooperateStatus(check::at(1));
  const auto array = node.latest<CooperateStatusArray>("/planning/cooperate_status/intersection");
  CHECK(array && array->statuses.size() == 2, "both register");
  if (array && array->statuses.size() == 2) {
    CHECK(std::isnan(array->statuses[0].start_distance), "a NaN distance is reported as given");
    CHECK(std::isinf(array->statuses[1].start_distance), "a double beyond float's range is infinite");
  }
  rtc.clearCooperateStatus();
  rtc.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 1, 1, check::at(0));
  rtc.updateCooperateStatus(id, true, State::RUNNING, 1, 1, check::at(0));
  rtc.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 1, 1, check::at(0));
  CHECK(log.warned("update refused"), "running cannot go back to waiting, and says so [COOP-DEV-SILENT-DROP.1]");
  CooperateCommands::Request bad = commands({{id, 9}});
  const auto reply = node.call<CooperateCommands>("/planning/cooperate_commands/intersection", bad);
  CHECK(reply && !reply->responses[0].success && log.warned("command"),
        "an undefined command type is refused [COOP-DEV-CONSTANTS.1]");
  rtc.updateCooperateStatus(check::uuid(4), true, State::WAITING_FOR_EXECUTION, 1, 1, check::at(0), false, false);
  CHECK(log.warned("override_rtc_auto_mode"), "an override against the module's policy is logged");
  CHECK(rtc.isActivated(check::uuid(4)), "and the scene follows its module's policy [COOP-DEV-AUTO-MODE-KEY.1]");
}

void sequences()
{
  Node node("planner");
  check::Log log(node);
  RTCInterface avoidance(&node, "static_obstacle_avoidance_left", true);
  const UUID out = check::uuid(20);
  avoidance.updateCooperateStatus(out, true, State::WAITING_FOR_EXECUTION, 5, 30, check::at(0));
  CHECK(log.warned("update refused") && !avoidance.isRegistered(out),
        "an avoidance scene needs its sequence [COOP-DEV-SEQUENCE.1]");
  avoidance.updateCooperateStatusIn("change", out, true, State::WAITING_FOR_EXECUTION, 5, 30, check::at(0));
  CHECK(avoidance.isRegistered(out), "stated, it registers");
  avoidance.updateCooperateStatusIn("sideways", check::uuid(21), true, State::WAITING_FOR_EXECUTION, 5, 30, check::at(0));
  CHECK(log.warned("update refused") && !avoidance.isRegistered(check::uuid(21)),
        "a sequence the interface does not bind is refused");
  avoidance.updateCooperateStatusIn(std::string("chan\xffge"), check::uuid(22), true,
                                    State::WAITING_FOR_EXECUTION, 5, 30, check::at(0));
  CHECK(log.warned("the sequence is not UTF-8") && !avoidance.isRegistered(check::uuid(22)),
        "a sequence that is not UTF-8 is refused, not thrown");
}
void a_quota_per_interface()
{
  Node node("planner");
  check::Log log(node);
  // The core is made by the first request for it: here, with a quota of one scene an interface.
  const auto core = cooperation::rtc::core_of(&node, 1);
  RTCInterface rtc(&node, "crosswalk", true);
  rtc.updateCooperateStatus(check::uuid(1), true, State::WAITING_FOR_EXECUTION, 1, 1, check::at(0));
  rtc.updateCooperateStatus(check::uuid(2), true, State::WAITING_FOR_EXECUTION, 1, 1, check::at(0));
  CHECK(rtc.isRegistered(check::uuid(1)) && !rtc.isRegistered(check::uuid(2)),
        "the second scene is over the quota [COOP-DEV-QUOTA.1]");
  CHECK(log.warned("the most it may have"), "and the refusal says so");
}
void the_nodes_default_quota()
{
  // Without a quota of its own, the core has the nodes' default: 215 live scenes an interface,
  // the core's 4,096 shared by the 19 interfaces.
  const auto quota = static_cast<unsigned>(cooperation::bridge::default_scene_quota());
  CHECK(quota == 215, "the nodes' default quota is 215");
  Node node("planner");
  check::Log log(node);
  RTCInterface rtc(&node, "crosswalk", true);
  for (unsigned n = 0; n < quota; ++n) {
    rtc.updateCooperateStatus(check::uuid(n), true, State::WAITING_FOR_EXECUTION, 1, 1, check::at(0));
  }
  CHECK(rtc.isRegistered(check::uuid(0)) && rtc.isRegistered(check::uuid(quota - 1)), "215 scenes register");
  CHECK(!log.warned("the most it may have"), "with no refusal");
  rtc.updateCooperateStatus(check::uuid(quota), true, State::WAITING_FOR_EXECUTION, 1, 1, check::at(0));
  CHECK(!rtc.isRegistered(check::uuid(quota)) && log.warned("the most it may have"),
        "the 216th is over the default quota [COOP-DEV-QUOTA.1]");
}
}  // namespace

int main()
{
  topics_services_and_timer();
  one_core_per_node();
  time_passes_once_a_cycle();
  names_without_a_binding();
  hostile_arguments();
  sequences();
  a_quota_per_interface();
  the_nodes_default_quota();
  return check::report("interface");
}
