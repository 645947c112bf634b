// Upstream's RTC interface (`autoware::rtc_interface::RTCInterface`), answered by the verified
// cooperation core: the same header path, namespace, class, fourteen public methods, topics and
// services, so that a planning module that includes this header and links
// `cooperation::rtc_interface` keeps its code. Every answer is the core's (one shared core per
// node, behind one lock); where upstream's answer is one of its quirks, the answer is the one
// the specification's deviations give (`spec/cooperation.md` section 9; `docs/cpp.md` lists
// them call for call). No method throws: a refusal is logged as a warning, as upstream logs
// its own.
//
// With rclcpp (CMake defines COOPERATION_RTC_WITH_RCLCPP where it finds it), `RTCInterface` is
// built on `rclcpp::Node` and the generated `tier4_rtc_msgs` types. Without it, on
// `cooperation::rtc::Node` and plain structs of the same names (`cooperation/rtc/messages.hpp`).
#ifndef AUTOWARE__RTC_INTERFACE__RTC_INTERFACE_HPP_
#define AUTOWARE__RTC_INTERFACE__RTC_INTERFACE_HPP_

#ifdef COOPERATION_RTC_WITH_RCLCPP
#include "rclcpp/rclcpp.hpp"

#include "tier4_rtc_msgs/msg/auto_mode_status.hpp"
#include "tier4_rtc_msgs/msg/command.hpp"
#include "tier4_rtc_msgs/msg/cooperate_command.hpp"
#include "tier4_rtc_msgs/msg/cooperate_response.hpp"
#include "tier4_rtc_msgs/msg/cooperate_status.hpp"
#include "tier4_rtc_msgs/msg/cooperate_status_array.hpp"
#include "tier4_rtc_msgs/msg/module.hpp"
#include "tier4_rtc_msgs/msg/state.hpp"
#include "tier4_rtc_msgs/srv/auto_mode.hpp"
#include "tier4_rtc_msgs/srv/cooperate_commands.hpp"
#include <unique_identifier_msgs/msg/uuid.hpp>
#else
#include "cooperation/rtc/messages.hpp"
#include "cooperation/rtc/node.hpp"
#endif

#include "cooperation/rtc/core.hpp"

#include <chrono>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace autoware::rtc_interface
{
using tier4_rtc_msgs::msg::AutoModeStatus;
using tier4_rtc_msgs::msg::Command;
using tier4_rtc_msgs::msg::CooperateCommand;
using tier4_rtc_msgs::msg::CooperateResponse;
using tier4_rtc_msgs::msg::CooperateStatus;
using tier4_rtc_msgs::msg::CooperateStatusArray;
using tier4_rtc_msgs::msg::Module;
using tier4_rtc_msgs::msg::State;
using tier4_rtc_msgs::srv::AutoMode;
using tier4_rtc_msgs::srv::CooperateCommands;
using unique_identifier_msgs::msg::UUID;

namespace detail
{
inline cooperation::rtc::Stamp stamp_of(const builtin_interfaces::msg::Time & time)
{
  return cooperation::rtc::Stamp{time.sec, time.nanosec};
}
inline builtin_interfaces::msg::Time time_of(cooperation::rtc::Stamp stamp)
{
  builtin_interfaces::msg::Time time;
  time.sec = stamp.sec;
  time.nanosec = stamp.nanosec;
  return time;
}
// `UUID::uuid` is a `std::array<uint8_t, 16>`, generated or plain, as the bridge's `bytes`.
inline cooperation::rtc::Uuid id_of(const UUID & uuid) { return cooperation::rtc::Uuid{uuid.uuid}; }
inline UUID uuid_of(const cooperation::rtc::Uuid & id)
{
  UUID uuid;
  uuid.uuid = id.bytes;
  return uuid;
}
/// The explanation of a refusal, for a log line.
inline std::string why(const cooperation::rtc::Result & result) { return std::string(result.warning); }
/// The UUID as 32 lowercase hexadecimal digits.
inline std::string to_string(const cooperation::rtc::Uuid & id)
{
  std::string text;
  char digits[3];
  for (const auto byte : id.bytes) {
    std::snprintf(digits, sizeof(digits), "%02x", static_cast<unsigned>(byte));
    text += digits;
  }
  return text;
}
/// A lifecycle state's name; a number no constant has is written as a number (upstream throws).
inline std::string state_name(uint8_t state)
{
  static const char * const names[] = {
    "WAITING_FOR_EXECUTION", "RUNNING", "ABORTING", "SUCCEEDED", "FAILED"};
  return state < 5 ? names[state] : "state " + std::to_string(state);
}
inline std::string command_name(uint8_t command)
{
  return command == Command::ACTIVATE     ? "ACTIVATE"
         : command == Command::DEACTIVATE ? "DEACTIVATE"
                                          : "command " + std::to_string(command);
}

#ifdef COOPERATION_RTC_WITH_RCLCPP
inline cooperation::rtc::Stamp stamp_of(const rclcpp::Time & time)
{
  return stamp_of(static_cast<builtin_interfaces::msg::Time>(time));
}
inline void warn(const rclcpp::Logger & logger, const std::string & text)
{
  RCLCPP_WARN(logger, "%s", text.c_str());
}
inline void info(const rclcpp::Logger & logger, const std::string & text)
{
  RCLCPP_INFO(logger, "%s", text.c_str());
}
#else
inline void warn(const cooperation::rtc::Logger & logger, const std::string & text)
{
  logger.warn(text);
}
inline void info(const cooperation::rtc::Logger & logger, const std::string & text)
{
  logger.info(text);
}
#endif
}  // namespace detail

#ifdef COOPERATION_RTC_WITH_RCLCPP
/// The node type `BasicRTCInterface<>` is built on, as upstream's default.
using DefaultNode = rclcpp::Node;
#else
/// The node type `BasicRTCInterface<>` is built on.
using DefaultNode = cooperation::rtc::Node;
#endif

/// Publishes the decision status of a planning module's scenes and receives the operator's
/// commands for them; every answer comes from the node's verified core.
template <class NodeT = DefaultNode>
class BasicRTCInterface
{
public:
  /// The node's time type: `rclcpp::Time`, or `builtin_interfaces::msg::Time` without rclcpp.
  using Time = decltype(std::declval<NodeT &>().now());

  /// The interface `name` on `node`, with upstream's topics and services. `enable_rtc = false`
  /// sets auto mode on: the interface's modules' policy becomes optional (true: required).
  /// Interfaces of the same core module share its policy (`[COOP-DEV-AUTO-MODE-KEY.1]`), so
  /// the last one made decides it. A name with no binding is logged and makes an interface
  /// whose queries answer false and whose changes are refused with a warning
  /// (`[COOP-DEV-INTERFACE-NAME.1]`); nothing throws. The interface keeps the node's clock and
  /// logger, and the node's core is found by the node's identity, not its address: the node may
  /// be destroyed first.
  BasicRTCInterface(NodeT * node, const std::string & name, const bool enable_rtc = true)
  : clock_(node->get_clock()),
    logger_(node->get_logger()),
    core_(cooperation::rtc::identity_of(node), name, enable_rtc)
  {
    module_.type = core_.module_type();
    if (!core_.bound().ok) {
      detail::warn(logger_, "RTC interface " + name + ": " + detail::why(core_.bound()));
    }
    pub_statuses_ = node->template create_publisher<CooperateStatusArray>(
      "/planning/cooperate_status/" + name, 1);
    pub_auto_mode_status_ =
      node->template create_publisher<AutoModeStatus>("/planning/auto_mode_status/" + name, 1);
    srv_commands_ = node->template create_service<CooperateCommands>(
      "/planning/cooperate_commands/" + name,
      [this](
        const typename CooperateCommands::Request::SharedPtr request,
        typename CooperateCommands::Response::SharedPtr response) {
        onCooperateCommandService(request, response);
      });
    srv_auto_mode_ = node->template create_service<AutoMode>(
      "/planning/enable_auto_mode/" + name,
      [this](
        const typename AutoMode::Request::SharedPtr request,
        typename AutoMode::Response::SharedPtr response) { onAutoModeService(request, response); });
    timer_ = node->create_wall_timer(std::chrono::milliseconds(100), [this] { onTimer(); });
  }

  BasicRTCInterface(const BasicRTCInterface &) = delete;
  BasicRTCInterface & operator=(const BasicRTCInterface &) = delete;

  /// Publishes the interface's live scenes, in identifier order, each stamped with its owner's
  /// last report (`stamp` less the scene's age). The array is the interface's own, written over
  /// in place: publishing allocates nothing of its own once the array has held its most scenes.
  void publishCooperateStatus(const Time & stamp)
  {
    const std::lock_guard<std::mutex> lock(publishing_);
    auto & array = published_;
    array.stamp = detail::time_of(detail::stamp_of(stamp));
    core_.statuses_into(detail::stamp_of(stamp), statuses_);
    array.statuses.resize(statuses_.size());
    auto status = array.statuses.begin();
    for (const auto & s : statuses_) {
      status->stamp = detail::time_of(s.stamp);
      status->uuid = detail::uuid_of(s.uuid);
      status->module.type = s.module;
      status->safe = s.safe;
      status->requested = s.requested;
      status->command_status.type = s.command;
      status->state.type = s.state;
      status->auto_mode = s.auto_mode;
      status->start_distance = s.start_distance;
      status->finish_distance = s.finish_distance;
      ++status;
    }
    pub_statuses_->publish(array);
  }

  /// The owner reports a scene: registers it if it is not live (and moves it to `state` in the
  /// same step where the lifecycle allows, `[COOP-DEV-REGISTER-PHASE.1]`), updates it otherwise.
  /// The report is made at the node clock's now: the core is told that time first, as
  /// `removeExpiredCooperateStatus` tells it, so the scene lives its time to live from now
  /// whichever of the two a module calls first (`[COOP-ENGINE-TIME.1]`); a step of the clock
  /// longer than the step limit (a jump) counts the limit (`[COOP-ENGINE-STEP.1]`). `stamp` is
  /// not read. `override_rtc_auto_mode` is honoured where it agrees with the
  /// module's policy, and otherwise logged: auto mode is a module's policy, not a scene's
  /// (`[COOP-DEV-AUTO-MODE-KEY.1]`). A refusal changes nothing and is logged
  /// (`[COOP-DEV-SILENT-DROP.1]`).
  void updateCooperateStatus(
    const UUID & uuid, const bool safe, const uint8_t state, const double start_distance,
    const double finish_distance, const Time & stamp, const bool requested = false,
    const std::optional<bool> & override_rtc_auto_mode = std::nullopt)
  {
    update(
      std::nullopt, uuid, safe, state, start_distance, finish_distance, stamp, requested,
      override_rtc_auto_mode);
  }

  /// `updateCooperateStatus` stating the scene's sequence (`"change"`, `"return"`), which an
  /// interface bound to several (the avoidances) needs to register a scene
  /// (`[COOP-DEV-SEQUENCE.1]`). Not in upstream.
  void updateCooperateStatusIn(
    const std::string & sequence, const UUID & uuid, const bool safe, const uint8_t state,
    const double start_distance, const double finish_distance, const Time & stamp,
    const bool requested = false)
  {
    update(sequence, uuid, safe, state, start_distance, finish_distance, stamp, requested, {});
  }

  /// Removes the scene; its identifier is never registered again (`[COOP-DEV-ID-REUSE.1]`).
  void removeCooperateStatus(const UUID & uuid) { logged("remove", uuid, core_.remove(detail::id_of(uuid))); }

  /// Tells the node's core the node's time: scenes not reported for the core's TTL (10 s by
  /// default) expire, and are logged. Every interface of the node may call it each cycle; time
  /// passes once (`[COOP-DEV-EXPIRY.1]`), and a step longer than the engine's step limit (1 s:
  /// a seek, the first `/clock`, a stalled planner) counts the limit (`[COOP-ENGINE-STEP.1]`).
  void removeExpiredCooperateStatus() { log_expired(core_.advance(now())); }

  /// Removes every live scene of this interface, all or none.
  void clearCooperateStatus()
  {
    const auto result = core_.clear();
    if (!result.ok) {
      detail::warn(logger_, core_.name() + ": clear refused: " + detail::why(result));
    }
  }

  /// The core's merged decision is activate; false for a scene that is not live, as upstream.
  bool isActivated(const UUID & uuid) const { return core_.is_activated(detail::id_of(uuid)); }
  /// The operator activated what the module would not (`[COOP-DEV-FORCE.1]`).
  bool isForceActivated(const UUID & uuid) const
  {
    return core_.is_force_activated(detail::id_of(uuid));
  }
  /// The operator deactivated what the module would do (`[COOP-DEV-FORCE.1]`).
  bool isForceDeactivated(const UUID & uuid) const
  {
    return core_.is_force_deactivated(detail::id_of(uuid));
  }
  /// The scene is live and registered through this interface.
  bool isRegistered(const UUID & uuid) const { return core_.is_registered(detail::id_of(uuid)); }
  /// The scene waits for the operator; false for a scene that is not live, where upstream
  /// answers its auto-mode flag (`[COOP-DEV-UNKNOWN-QUERY.1]`).
  bool isRTCEnabled(const UUID & uuid) const
  {
    return core_.is_rtc_enabled(detail::id_of(uuid)).value_or(false);
  }
  /// The scene succeeded or failed (it retired then, `[COOP-DEV-TERMINAL.1]`); false for one
  /// this interface never registered, where upstream answers its auto-mode flag
  /// (`[COOP-DEV-UNKNOWN-QUERY.1]`).
  bool isTerminated(const UUID & uuid) const
  {
    return core_.is_terminated(detail::id_of(uuid)).value_or(false);
  }

  /// Does nothing: commands apply at once, under the core's lock, and none is stored to apply
  /// later (`[COOP-DEV-STORED-COMMANDS.1]`, `[COOP-DEV-RACE.1]`).
  void lockCommandUpdate() {}
  /// Does nothing (see `lockCommandUpdate`).
  void unlockCommandUpdate() {}

  /// Logs each live scene: uuid, command, safe, state.
  void print() const
  {
    for (const auto & s : core_.statuses(now())) {
      detail::info(
        logger_, "uuid : " + detail::to_string(s.uuid) +
                               " command : " + detail::command_name(s.command) +
                               " safe : " + (s.safe ? "true" : "false") +
                               " state : " + detail::state_name(s.state));
    }
  }

  /// The interface in the core: whether its name is bound, and the calls beneath this class.
  const cooperation::rtc::InterfaceCore & core() const { return core_; }

  /// Upstream's unit test reaches `updateCooperateCommandStatus` and `stored_commands_` through
  /// its fixture, `RTCInterfaceTest`; both are here, with upstream's signatures, for that test.
  friend class RTCInterfaceTest;

private:
  /// Applies `commands` as the CooperateCommands service does: one batch, all or nothing
  /// (`[COOP-DEV-BATCH.1]`), a refusal logged. Upstream's private method.
  void updateCooperateCommandStatus(const std::vector<CooperateCommand> & commands)
  {
    apply(commands);
  }

  /// What the core answered `commands`, made at the node clock's now (the core is told it
  /// first, `[COOP-ENGINE-TIME.1]`), entry for entry; a refusal is logged.
  cooperation::rtc::Answered apply(const std::vector<CooperateCommand> & commands)
  {
    std::vector<cooperation::rtc::CommandIn> in;
    in.reserve(commands.size());
    for (const auto & command : commands) {
      in.push_back(
        cooperation::rtc::CommandIn{detail::id_of(command.uuid), command.module.type, command.command.type});
    }
    auto answered = core_.cooperate_commands(now(), in);
    log_expired(answered.expired);
    if (!answered.outcome.ok) {
      detail::warn(
        logger_, core_.name() + ": commands refused: " + detail::why(answered.outcome));
    }
    return answered;
  }

  /// The node clock's now, as the core is told it.
  cooperation::rtc::Stamp now() const { return detail::stamp_of(clock_->now()); }

  /// Logs the scenes the core said expired.
  template <class Uuids>
  void log_expired(const Uuids & expired) const
  {
    // Most calls expire nothing: one call into the bridge, not the loop's two ends.
    if (expired.empty()) {
      return;
    }
    for (const auto & uuid : expired) {
      detail::info(logger_, "uuid : " + detail::to_string(uuid) + " expired");
    }
  }

  void update(
    const std::optional<std::string> & sequence, const UUID & uuid, const bool safe,
    const uint8_t state, const double start_distance, const double finish_distance, const Time &,
    const bool requested, const std::optional<bool> & override_rtc_auto_mode)
  {
    const auto bytes = detail::id_of(uuid);
    if (
      override_rtc_auto_mode && !core_.is_registered(bytes) &&
      *override_rtc_auto_mode != core_.auto_mode_status()) {
      detail::warn(
        logger_, "uuid : " + detail::to_string(bytes) +
                               " override_rtc_auto_mode is not honoured: a scene follows its "
                               "module's policy [COOP-DEV-AUTO-MODE-KEY.1]");
    }
    const auto told =
      core_.update(now(), bytes, safe, state, start_distance, finish_distance, requested, sequence);
    log_expired(told.expired);
    logged("update", uuid, told.outcome);
  }

  void logged(const char * what, const UUID & uuid, const cooperation::rtc::Result & result) const
  {
    if (!result.ok) {
      detail::warn(
        logger_, "uuid : " + detail::to_string(detail::id_of(uuid)) + " " + what +
                               " refused: " + detail::why(result));
    }
  }

  void onCooperateCommandService(
    const typename CooperateCommands::Request::SharedPtr request,
    const typename CooperateCommands::Response::SharedPtr response)
  {
    // The adapter's response, entry for entry ([COOP-DEV-BATCH.1]: each says whether the batch
    // applied).
    const auto answered = apply(request->commands);
    response->responses.reserve(answered.responses.size());
    for (const auto & entry : answered.responses) {
      CooperateResponse answer;
      answer.uuid = detail::uuid_of(entry.uuid);
      answer.module.type = entry.module;
      answer.success = entry.success;
      response->responses.push_back(answer);
    }
  }

  void onAutoModeService(
    const typename AutoMode::Request::SharedPtr request,
    const typename AutoMode::Response::SharedPtr response)
  {
    const auto told = core_.auto_mode(now(), request->enable);
    log_expired(told.expired);
    response->success = told.outcome.ok;
    if (!told.outcome.ok) {
      detail::warn(logger_, core_.name() + ": auto mode refused: " + detail::why(told.outcome));
    }
  }

  void onTimer()
  {
    AutoModeStatus status;
    status.module = module_;
    status.is_auto_mode = core_.auto_mode_status();
    pub_auto_mode_status_->publish(status);
  }

  using CooperateStatusPublisherPtr =
    decltype(std::declval<NodeT *>()->template create_publisher<CooperateStatusArray>(
      std::string{}, 1));
  using AutoModeStatusPublisherPtr =
    decltype(std::declval<NodeT *>()->template create_publisher<AutoModeStatus>(std::string{}, 1));

  // What the interface needs of its node after construction, kept: it may outlive the node.
  decltype(std::declval<NodeT &>().get_clock()) clock_;
  std::decay_t<decltype(std::declval<NodeT &>().get_logger())> logger_;
  cooperation::rtc::InterfaceCore core_;
  Module module_;
  CooperateStatusPublisherPtr pub_statuses_;
  AutoModeStatusPublisherPtr pub_auto_mode_status_;
  std::shared_ptr<void> srv_commands_;
  std::shared_ptr<void> srv_auto_mode_;
  std::shared_ptr<void> timer_;
  /// The array `publishCooperateStatus` publishes and the bridge's statuses it is made from,
  /// both kept between calls, under their own lock: publishing from two threads is safe, as
  /// upstream's.
  std::mutex publishing_;
  CooperateStatusArray published_;
  rust::Vec<cooperation::rtc::Status> statuses_;
  /// Always empty: no command is stored to apply later (`[COOP-DEV-STORED-COMMANDS.1]`).
  /// Upstream's member, which its unit test reads.
  std::vector<CooperateCommand> stored_commands_;
};

using RTCInterface = BasicRTCInterface<>;

}  // namespace autoware::rtc_interface

#endif  // AUTOWARE__RTC_INTERFACE__RTC_INTERFACE_HPP_
