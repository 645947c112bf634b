// The node's core and its interfaces: each call converts its arguments to the bridge's types,
// makes one bridge call, and converts the answer back. A string that is not UTF-8 (which the
// bridge cannot carry) is refused here with a warning; nothing throws out of this file.
#include "cooperation/rtc/core.hpp"

#include "cooperation-cpp/src/bridge.rs.h"

#include <exception>
#include <map>
#include <mutex>
#include <utility>

namespace cooperation::rtc
{
namespace b = ::cooperation::bridge;

/// One node's core.
class NodeCore
{
public:
  explicit NodeCore(rust::Box<b::Core> core) : core(std::move(core)) {}
  rust::Box<b::Core> core;
};

namespace
{
b::Uuid to_bridge(const Bytes & bytes)
{
  b::Uuid uuid{};
  uuid.bytes = bytes;
  return uuid;
}

b::Stamp to_bridge(Stamp stamp) { return b::Stamp{stamp.sec, stamp.nanosec}; }

Result from_bridge(const b::Outcome & outcome)
{
  return Result{outcome.ok, std::string(outcome.warning)};
}

/// `text` as the bridge's string, or why it cannot be one.
std::optional<rust::String> utf8(const std::string & text, std::string & why)
{
  try {
    return rust::String(text);
  } catch (const std::exception & e) {
    why = e.what();
    return std::nullopt;
  }
}

Result refused(std::string why) { return Result{false, std::move(why)}; }
}  // namespace

std::shared_ptr<NodeCore> core_of(const void * node, std::size_t quota)
{
  static std::mutex mutex;
  static std::map<const void *, std::weak_ptr<NodeCore>> cores;
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto core = cores[node].lock()) {
    return core;
  }
  // The standard bindings are a valid configuration, so this does not throw; if it ever did,
  // the node could not run, and its constructor is where upstream's throws too.
  auto core = std::make_shared<NodeCore>(b::new_core(quota));
  cores[node] = core;
  // Forget the nodes whose cores are gone.
  for (auto it = cores.begin(); it != cores.end();) {
    it = it->second.expired() ? cores.erase(it) : std::next(it);
  }
  return core;
}

InterfaceCore::InterfaceCore(const void * node, const std::string & name, bool enable_rtc)
: core_(core_of(node)), name_(name)
{
  std::string why;
  if (!utf8(name_, why)) {
    bound_ = refused("the interface name is not UTF-8: " + why);
    return;
  }
  bound_ = from_bridge(b::bind(*core_->core, name_, enable_rtc));
}

InterfaceCore::~InterfaceCore() = default;
InterfaceCore::InterfaceCore(InterfaceCore &&) noexcept = default;
InterfaceCore & InterfaceCore::operator=(InterfaceCore &&) noexcept = default;

const Result & InterfaceCore::bound() const { return bound_; }
const std::string & InterfaceCore::name() const { return name_; }

uint8_t InterfaceCore::module_type() const
{
  return bound_.ok ? b::module_type(*core_->core, name_) : 0;
}

Result InterfaceCore::update(
  const Bytes & uuid, bool safe, uint8_t state, double start_distance, double finish_distance,
  bool requested, const std::optional<std::string> & sequence)
{
  if (!bound_.ok) {
    return bound_;
  }
  std::string why;
  const auto stated = sequence ? utf8(*sequence, why) : std::optional<rust::String>{};
  if (sequence && !stated) {
    return refused("the sequence is not UTF-8: " + why);
  }
  const b::Uuid id = to_bridge(uuid);
  return from_bridge(b::update(
    *core_->core, name_, id, safe, state, start_distance, finish_distance, requested,
    stated.has_value(), stated ? rust::Str(*stated) : rust::Str()));
}

Result InterfaceCore::remove(const Bytes & uuid)
{
  if (!bound_.ok) {
    return bound_;
  }
  const b::Uuid id = to_bridge(uuid);
  return from_bridge(b::remove(*core_->core, name_, id));
}

Result InterfaceCore::clear()
{
  return bound_.ok ? from_bridge(b::clear(*core_->core, name_)) : bound_;
}

std::vector<Bytes> InterfaceCore::advance(Stamp now)
{
  std::vector<Bytes> expired;
  for (const auto & uuid : b::advance(*core_->core, to_bridge(now))) {
    expired.push_back(uuid.bytes);
  }
  return expired;
}

#define COOPERATION_QUERY(method)                                   \
  bool InterfaceCore::method(const Bytes & uuid) const              \
  {                                                                 \
    const b::Uuid id = to_bridge(uuid);                             \
    return bound_.ok && b::method(*core_->core, name_, id);         \
  }
COOPERATION_QUERY(is_registered)
COOPERATION_QUERY(is_activated)
COOPERATION_QUERY(is_force_activated)
COOPERATION_QUERY(is_force_deactivated)
#undef COOPERATION_QUERY

std::optional<bool> InterfaceCore::is_rtc_enabled(const Bytes & uuid) const
{
  if (!bound_.ok) {
    return std::nullopt;
  }
  const auto flag = b::is_rtc_enabled(*core_->core, name_, to_bridge(uuid));
  return flag.known ? std::optional<bool>(flag.value) : std::nullopt;
}

std::optional<bool> InterfaceCore::is_terminated(const Bytes & uuid) const
{
  if (!bound_.ok) {
    return std::nullopt;
  }
  const auto flag = b::is_terminated(*core_->core, name_, to_bridge(uuid));
  return flag.known ? std::optional<bool>(flag.value) : std::nullopt;
}

std::vector<Status> InterfaceCore::statuses(Stamp stamp) const
{
  std::vector<Status> out;
  if (!bound_.ok) {
    return out;
  }
  for (const auto & s : b::statuses(*core_->core, name_, to_bridge(stamp))) {
    out.push_back(Status{
      Stamp{s.stamp.sec, s.stamp.nanosec}, s.uuid.bytes, s.module, s.safe, s.requested,
      s.command, s.state, s.auto_mode, s.start_distance, s.finish_distance});
  }
  return out;
}

bool InterfaceCore::auto_mode_status() const
{
  return bound_.ok && b::auto_mode_status(*core_->core, name_);
}

Result InterfaceCore::cooperate_commands(const std::vector<CommandIn> & commands)
{
  if (!bound_.ok) {
    return bound_;
  }
  std::vector<b::CommandIn> in;
  in.reserve(commands.size());
  for (const auto & c : commands) {
    in.push_back(b::CommandIn{to_bridge(c.uuid), c.module, c.command});
  }
  return from_bridge(
    b::cooperate_commands(*core_->core, name_, rust::Slice<const b::CommandIn>(in.data(), in.size())));
}

Result InterfaceCore::auto_mode(bool enable)
{
  return bound_.ok ? from_bridge(b::auto_mode(*core_->core, name_, enable)) : bound_;
}
}  // namespace cooperation::rtc
