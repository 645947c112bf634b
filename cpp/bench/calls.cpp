// Per-call cost of the C++ class's methods (docs/performance.md, "The C++ RTC interface"), at
// 1, 3, 10, 100 and 1,000 live scenes in one interface, and of a planning cycle in upstream's
// velocity planner's call order (`planningCycle`), beside two baselines measured in the same
// run: the same calls made in Rust on the Rust side of the bridge (no C++ boundary), and an
// upstream-style registry (a vector searched linearly under a mutex, as `rtc_interface` keeps
// its statuses), written here only to be measured. Built by `tools/cpp`; run it by hand:
//   target/cpp/build/bench_calls
#include "autoware/rtc_interface/rtc_interface.hpp"
#include "cooperation-cpp/src/bridge.rs.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

using autoware::rtc_interface::Command;
using autoware::rtc_interface::CooperateCommand;
using autoware::rtc_interface::CooperateCommands;
using autoware::rtc_interface::CooperateStatus;
using autoware::rtc_interface::CooperateStatusArray;
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

/// Upstream's data model for the same calls: statuses in a vector searched linearly.
class LinearRegistry
{
public:
  void update(const UUID & uuid, bool safe, uint8_t state, double start, double finish)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto * status = find(uuid);
    if (status == nullptr) {
      CooperateStatus added;
      added.uuid = uuid;
      added.safe = safe;
      added.state.type = State::WAITING_FOR_EXECUTION;
      added.start_distance = static_cast<float>(start);
      added.finish_distance = static_cast<float>(finish);
      added.auto_mode = true;
      statuses_.push_back(added);
      return;
    }
    status->safe = safe;
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
  bool command(const std::vector<CooperateCommand> & commands)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    bool all = true;
    for (const auto & c : commands) {
      auto * s = find(c.uuid);
      all = all && s != nullptr;
      if (s != nullptr) {
        s->command_status = c.command;
        s->auto_mode = false;
      }
    }
    return all;
  }
  CooperateStatusArray publish()
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    CooperateStatusArray array;
    array.statuses = statuses_;
    return array;
  }
  void remove_expired(int32_t now)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    statuses_.erase(
      std::remove_if(statuses_.begin(), statuses_.end(),
                     [now](const CooperateStatus & s) { return now - s.stamp.sec > 10; }),
      statuses_.end());
  }

private:
  CooperateStatus * find(const UUID & uuid)
  {
    for (auto & status : statuses_) {
      if (status.uuid.uuid == uuid.uuid) {
        return &status;
      }
    }
    return nullptr;
  }
  std::mutex mutex_;
  std::vector<CooperateStatus> statuses_;
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
  LinearRegistry registry;
  for (std::size_t i = 0; i < scenes; ++i) {
    registry.update(scene(i), true, State::WAITING_FOR_EXECUTION, 10, 10);
  }
  const auto at = [scenes](std::size_t round) { return scene(round % scenes); };
  std::map<std::string, double> ns;
  ns["updateCooperateStatus"] = time_ns(rounds, [&](std::size_t r) {
    registry.update(at(r), true, State::WAITING_FOR_EXECUTION, 10, 10);
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
    CooperateCommand command;
    command.uuid = at(r);
    command.command.type = Command::ACTIVATE;
    sink = registry.command({command});
  });
  ns["publishCooperateStatus"] = time_ns(
    (rounds + scenes - 1) / scenes, [&](std::size_t) { sink = registry.publish().statuses.empty(); });
  ns["removeExpiredCooperateStatus"] = time_ns(rounds, [&](std::size_t) { registry.remove_expired(0); });
  ns["planningCycle"] = time_ns((rounds + scenes - 1) / scenes, [&](std::size_t) {
    for (std::size_t i = 0; i < scenes; ++i) {
      sink = registry.is_activated(scene(i));
      sink = registry.is_rtc_enabled(scene(i));
    }
    for (std::size_t i = 0; i < scenes; ++i) {
      registry.update(scene(i), true, State::WAITING_FOR_EXECUTION, 10, 10);
    }
    registry.remove_expired(0);
    sink = registry.publish().statuses.empty();
  });
  return ns;
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
  return 0;
}
