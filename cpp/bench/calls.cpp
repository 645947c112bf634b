// Per-call cost of the C++ class's methods (docs/performance-cpp.md), at
// 1, 3, 10, 100 and 1,000 live scenes in one interface, and of a planning cycle in upstream's
// velocity planner's call order (`planningCycle`), beside two baselines measured in the same
// run: the same calls made in Rust on the Rust side of the bridge (no C++ boundary), and an
// upstream-style registry (`LinearRegistry`: what upstream's `RTCInterface` does for each call,
// on the same node), written here only to be measured. Then the cycle of a node with the
// velocity planner's nine interfaces, 1, 3 and 10 scenes each, against nine registries.
// Built by `tools/cpp`; run it by hand:
//   target/cpp/build/bench_calls
#include "autoware/rtc_interface/rtc_interface.hpp"
#include "cooperation-cpp/src/bridge.rs.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

using autoware::rtc_interface::Command;
using autoware::rtc_interface::CooperateCommand;
using autoware::rtc_interface::CooperateCommands;
using autoware::rtc_interface::CooperateResponse;
using autoware::rtc_interface::CooperateStatus;
using autoware::rtc_interface::CooperateStatusArray;
using autoware::rtc_interface::Module;
using autoware::rtc_interface::RTCInterface;
using autoware::rtc_interface::State;
using autoware::rtc_interface::UUID;

namespace
{
UUID scene(std::size_t index)
{
  UUID id;
  const auto n = static_cast<uint64_t>(index + 1);
  for (int i = 0; i < 8; ++i) {
    id.uuid[15 - i] = static_cast<uint8_t>(n >> (8 * i));
  }
  return id;
}

volatile bool sink;

double time_ns(std::size_t rounds, const std::function<void(std::size_t)> & call)
{
  rounds = std::max<std::size_t>(rounds, 1);
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t round = 0; round < rounds; ++round) {
    call(round);
  }
  const std::chrono::duration<double, std::nano> took = std::chrono::steady_clock::now() - start;
  return took.count() / static_cast<double>(rounds);
}

/// Upstream's `RTCInterface` for the same calls, as it behaves: statuses in the array it
/// publishes, searched linearly under one mutex; an update checked against the lifecycle's
/// transition table and stamped with the caller's time; expiry against the node's clock; commands
/// through the node's service, one response per command; the array published through the node.
class LinearRegistry
{
public:
  LinearRegistry(cooperation::rtc::Node & node, const std::string & name)
  : node_(node),
    publisher_(node.create_publisher<CooperateStatusArray>("/registry/cooperate_status/" + name, 1))
  {
    server_ = node.create_service<CooperateCommands>(
      "/registry/cooperate_commands/" + name, [this](
                 const CooperateCommands::Request::SharedPtr request,
                 const CooperateCommands::Response::SharedPtr response) {
        on_commands(*request, *response);
      });
  }

  void update(
    const UUID & uuid, bool safe, uint8_t state, double start, double finish,
    const builtin_interfaces::msg::Time & stamp, bool requested = false)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto * status = find(uuid);
    if (status == nullptr) {
      CooperateStatus added;
      added.stamp = stamp;
      added.uuid = uuid;
      added.module.type = Module::INTERSECTION;
      added.safe = safe;
      added.requested = requested;
      added.command_status.type = Command::DEACTIVATE;
      added.state.type = State::WAITING_FOR_EXECUTION;
      added.start_distance = static_cast<float>(start);
      added.finish_distance = static_cast<float>(finish);
      added.auto_mode = true;
      registered_.statuses.push_back(added);
      return;
    }
    if (!may_transit(status->state.type, state)) {
      return;
    }
    status->stamp = stamp;
    status->safe = safe;
    status->requested = requested;
    status->state.type = state;
    status->start_distance = static_cast<float>(start);
    status->finish_distance = static_cast<float>(finish);
  }
  bool is_registered(const UUID & uuid)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    return find(uuid) != nullptr;
  }
  bool is_activated(const UUID & uuid)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto * s = find(uuid);
    return s != nullptr && (s->auto_mode && !s->requested ? s->safe
                                                          : s->command_status.type == Command::ACTIVATE);
  }
  bool is_force_activated(const UUID & uuid)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto * s = find(uuid);
    return s != nullptr && s->command_status.type == Command::ACTIVATE && (!s->safe || s->requested);
  }
  bool is_force_deactivated(const UUID & uuid)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto * s = find(uuid);
    return s != nullptr && s->state.type == State::RUNNING &&
           s->command_status.type == Command::DEACTIVATE && s->safe && !s->auto_mode;
  }
  bool is_rtc_enabled(const UUID & uuid)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto * s = find(uuid);
    return s != nullptr && !s->auto_mode;
  }
  bool is_terminated(const UUID & uuid)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto * s = find(uuid);
    return s != nullptr && (s->state.type == State::SUCCEEDED || s->state.type == State::FAILED);
  }
  void publish(const builtin_interfaces::msg::Time & stamp)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    registered_.stamp = stamp;
    publisher_->publish(registered_);
  }
  void remove_expired()
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto now = seconds(node_.now());
    registered_.statuses.erase(
      std::remove_if(
        registered_.statuses.begin(), registered_.statuses.end(),
        [now](const CooperateStatus & s) { return now - seconds(s.stamp) > 10.0; }),
      registered_.statuses.end());
  }

private:
  static double seconds(const builtin_interfaces::msg::Time & time)
  {
    return static_cast<double>(time.sec) + static_cast<double>(time.nanosec) * 1e-9;
  }
  // The four rules of upstream's table: from waiting to waiting, running or failed; from running
  // to anything but waiting; from aborting to aborting or failed; to the same state.
  static bool may_transit(uint8_t from, uint8_t to)
  {
    return (from == State::WAITING_FOR_EXECUTION &&
            (to == State::WAITING_FOR_EXECUTION || to == State::RUNNING || to == State::FAILED)) ||
           (from == State::RUNNING && to != State::WAITING_FOR_EXECUTION) ||
           (from == State::ABORTING && (to == State::ABORTING || to == State::FAILED)) ||
           to == from;
  }
  static bool commandable(const CooperateStatus * s)
  {
    return s != nullptr &&
           (s->state.type == State::WAITING_FOR_EXECUTION || s->state.type == State::RUNNING);
  }
  // One response per command, then each command applied to its scene if that is waiting or
  // running (upstream's command lock is never taken here).
  void on_commands(
    const CooperateCommands::Request & request, CooperateCommands::Response & response)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto & c : request.commands) {
      CooperateResponse answer;
      answer.uuid = c.uuid;
      answer.module = c.module;
      answer.success = commandable(find(c.uuid));
      response.responses.push_back(answer);
    }
    for (const auto & c : request.commands) {
      auto * s = find(c.uuid);
      if (commandable(s)) {
        s->command_status = c.command;
        s->auto_mode = false;
      }
    }
  }
  CooperateStatus * find(const UUID & uuid)
  {
    for (auto & status : registered_.statuses) {
      if (status.uuid.uuid == uuid.uuid) {
        return &status;
      }
    }
    return nullptr;
  }
  cooperation::rtc::Node & node_;
  std::mutex mutex_;
  CooperateStatusArray registered_;
  cooperation::rtc::Publisher<CooperateStatusArray>::SharedPtr publisher_;
  std::shared_ptr<cooperation::rtc::ServiceServer<CooperateCommands>> server_;
};

std::map<std::string, double> time_class(std::size_t scenes, std::size_t rounds)
{
  cooperation::rtc::Node node("bench");
  // Up to 1,000 scenes in one interface: no quota, as the Rust baseline's core.
  const auto core = cooperation::rtc::core_of(&node, 0);
  RTCInterface rtc(&node, "intersection", false);
  for (std::size_t i = 0; i < scenes; ++i) {
    rtc.updateCooperateStatus(scene(i), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
  }
  const auto at = [scenes](std::size_t round) { return scene(round % scenes); };
  std::map<std::string, double> ns;
  ns["updateCooperateStatus"] = time_ns(rounds, [&](std::size_t r) {
    rtc.updateCooperateStatus(at(r), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
  });
  ns["isRegistered"] = time_ns(rounds, [&](std::size_t r) { sink = rtc.isRegistered(at(r)); });
  ns["isActivated"] = time_ns(rounds, [&](std::size_t r) { sink = rtc.isActivated(at(r)); });
  ns["isForceActivated"] = time_ns(rounds, [&](std::size_t r) { sink = rtc.isForceActivated(at(r)); });
  ns["isForceDeactivated"] =
    time_ns(rounds, [&](std::size_t r) { sink = rtc.isForceDeactivated(at(r)); });
  ns["isRTCEnabled"] = time_ns(rounds, [&](std::size_t r) { sink = rtc.isRTCEnabled(at(r)); });
  ns["isTerminated"] = time_ns(rounds, [&](std::size_t r) { sink = rtc.isTerminated(at(r)); });
  ns["cooperateCommands"] = time_ns(rounds, [&](std::size_t r) {
    CooperateCommands::Request request;
    CooperateCommand command;
    command.uuid = at(r);
    command.command.type = Command::ACTIVATE;
    request.commands.push_back(command);
    sink = node.call<CooperateCommands>("/planning/cooperate_commands/intersection", request)
             .has_value();
  });
  ns["publishCooperateStatus"] =
    time_ns((rounds + scenes - 1) / scenes, [&](std::size_t) { rtc.publishCooperateStatus(node.now()); });
  ns["removeExpiredCooperateStatus"] =
    time_ns(rounds, [&](std::size_t) { rtc.removeExpiredCooperateStatus(); });
  ns["planningCycle"] = time_ns((rounds + scenes - 1) / scenes, [&](std::size_t) {
    for (std::size_t i = 0; i < scenes; ++i) {
      sink = rtc.isActivated(scene(i));
      sink = rtc.isRTCEnabled(scene(i));
    }
    for (std::size_t i = 0; i < scenes; ++i) {
      rtc.updateCooperateStatus(scene(i), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
    }
    rtc.removeExpiredCooperateStatus();
    rtc.publishCooperateStatus(node.now());
  });
  return ns;
}

std::map<std::string, double> time_linear(std::size_t scenes, std::size_t rounds)
{
  cooperation::rtc::Node node("bench");
  LinearRegistry registry(node, "intersection");
  for (std::size_t i = 0; i < scenes; ++i) {
    registry.update(scene(i), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
  }
  const auto at = [scenes](std::size_t round) { return scene(round % scenes); };
  std::map<std::string, double> ns;
  ns["updateCooperateStatus"] = time_ns(rounds, [&](std::size_t r) {
    registry.update(at(r), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
  });
  ns["isRegistered"] = time_ns(rounds, [&](std::size_t r) { sink = registry.is_registered(at(r)); });
  ns["isActivated"] = time_ns(rounds, [&](std::size_t r) { sink = registry.is_activated(at(r)); });
  ns["isForceActivated"] =
    time_ns(rounds, [&](std::size_t r) { sink = registry.is_force_activated(at(r)); });
  ns["isForceDeactivated"] =
    time_ns(rounds, [&](std::size_t r) { sink = registry.is_force_deactivated(at(r)); });
  ns["isRTCEnabled"] = time_ns(rounds, [&](std::size_t r) { sink = registry.is_rtc_enabled(at(r)); });
  ns["isTerminated"] = time_ns(rounds, [&](std::size_t r) { sink = registry.is_terminated(at(r)); });
  ns["cooperateCommands"] = time_ns(rounds, [&](std::size_t r) {
    CooperateCommands::Request request;
    CooperateCommand command;
    command.uuid = at(r);
    command.command.type = Command::ACTIVATE;
    request.commands.push_back(command);
    sink = node.call<CooperateCommands>("/registry/cooperate_commands/intersection", request)
             .has_value();
  });
  ns["publishCooperateStatus"] =
    time_ns((rounds + scenes - 1) / scenes, [&](std::size_t) { registry.publish(node.now()); });
  ns["removeExpiredCooperateStatus"] =
    time_ns(rounds, [&](std::size_t) { registry.remove_expired(); });
  ns["planningCycle"] = time_ns((rounds + scenes - 1) / scenes, [&](std::size_t) {
    for (std::size_t i = 0; i < scenes; ++i) {
      sink = registry.is_activated(scene(i));
      sink = registry.is_rtc_enabled(scene(i));
    }
    for (std::size_t i = 0; i < scenes; ++i) {
      registry.update(scene(i), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
    }
    registry.remove_expired();
    registry.publish(node.now());
  });
  return ns;
}
/// The velocity planner's nine interfaces, each a module of its own.
const std::vector<std::string> kVelocityInterfaces = {
  "intersection", "intersection_occlusion", "crosswalk", "blind_spot", "traffic_light",
  "virtual_traffic_light", "detection_area", "no_stopping_area", "roundabout"};

/// The identifier of scene `index` of interface `interface`: distinct across interfaces.
UUID node_scene(std::size_t interface, std::size_t index) { return scene(interface * 10000 + index); }

/// One planning cycle of every interface of a node (each interface's `planningCycle` in turn),
/// nanoseconds per cycle of one interface: `Cycle(interface)` runs one interface's.
template <typename Cycle>
double time_node_cycles(std::size_t scenes, std::size_t rounds, std::size_t interfaces, Cycle cycle)
{
  return time_ns((rounds + scenes - 1) / scenes, [&](std::size_t) {
           for (std::size_t k = 0; k < interfaces; ++k) {
             cycle(k);
           }
         }) /
         static_cast<double>(interfaces);
}

/// The class's cycle of a node with the velocity planner's nine interfaces, per interface.
double time_class_node(std::size_t scenes, std::size_t rounds)
{
  cooperation::rtc::Node node("bench");
  const auto core = cooperation::rtc::core_of(&node, 0);
  std::vector<std::unique_ptr<RTCInterface>> rtcs;
  for (const auto & name : kVelocityInterfaces) {
    rtcs.push_back(std::make_unique<RTCInterface>(&node, name, false));
  }
  for (std::size_t k = 0; k < rtcs.size(); ++k) {
    for (std::size_t i = 0; i < scenes; ++i) {
      rtcs[k]->updateCooperateStatus(
        node_scene(k, i), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
    }
  }
  return time_node_cycles(scenes, rounds, rtcs.size(), [&](std::size_t k) {
    auto & rtc = *rtcs[k];
    for (std::size_t i = 0; i < scenes; ++i) {
      sink = rtc.isActivated(node_scene(k, i));
      sink = rtc.isRTCEnabled(node_scene(k, i));
    }
    for (std::size_t i = 0; i < scenes; ++i) {
      rtc.updateCooperateStatus(
        node_scene(k, i), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
    }
    rtc.removeExpiredCooperateStatus();
    rtc.publishCooperateStatus(node.now());
  });
}

/// Nine upstream-style registries on one node, the same cycle, per interface.
double time_linear_node(std::size_t scenes, std::size_t rounds)
{
  cooperation::rtc::Node node("bench");
  std::vector<std::unique_ptr<LinearRegistry>> registries;
  for (const auto & name : kVelocityInterfaces) {
    registries.push_back(std::make_unique<LinearRegistry>(node, name));
  }
  for (std::size_t k = 0; k < registries.size(); ++k) {
    for (std::size_t i = 0; i < scenes; ++i) {
      registries[k]->update(node_scene(k, i), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
    }
  }
  return time_node_cycles(scenes, rounds, registries.size(), [&](std::size_t k) {
    auto & registry = *registries[k];
    for (std::size_t i = 0; i < scenes; ++i) {
      sink = registry.is_activated(node_scene(k, i));
      sink = registry.is_rtc_enabled(node_scene(k, i));
    }
    for (std::size_t i = 0; i < scenes; ++i) {
      registry.update(node_scene(k, i), true, State::WAITING_FOR_EXECUTION, 10, 10, node.now());
    }
    registry.remove_expired();
    registry.publish(node.now());
  });
}
}  // namespace

int main(int argc, char ** argv)
{
  const std::size_t rounds = argc > 1 ? std::stoul(argv[1]) : 200000;
  std::printf(
    "| method | scenes | C++ class (ns) | Rust, no boundary (ns) | upstream-style registry (ns) | "
    "class / Rust | class / upstream-style |\n|---|---:|---:|---:|---:|---:|---:|\n");
  for (const std::size_t scenes : {1, 3, 10, 100, 1000}) {
    const auto cpp = time_class(scenes, rounds);
    const auto linear = time_linear(scenes, rounds);
    std::map<std::string, double> rust;
    for (const auto & cost : cooperation::bridge::time_rust_calls(scenes, rounds)) {
      rust[std::string(cost.method)] = cost.nanos;
    }
    for (const auto & [method, ns] : cpp) {
      std::printf("| %s | %zu | %.0f | %.0f | %.0f | %.2f | %.2f |\n", method.c_str(), scenes, ns,
                  rust[method], linear.at(method), ns / rust[method], ns / linear.at(method));
    }
  }
  std::printf(
    "\n| cycle of a node of nine interfaces | scenes each | C++ class (ns an interface) | "
    "upstream-style registries (ns an interface) | class / upstream-style |\n"
    "|---|---:|---:|---:|---:|\n");
  for (const std::size_t scenes : {1, 3, 10}) {
    const double cpp = time_class_node(scenes, rounds);
    const double linear = time_linear_node(scenes, rounds);
    std::printf("| planningCycle | %zu | %.0f | %.0f | %.2f |\n", scenes, cpp, linear, cpp / linear);
  }
  return 0;
}
