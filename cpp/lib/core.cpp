// The node's core and its interfaces: each call is one bridge call, its arguments and answer
// the bridge's own types. A string that is not UTF-8 (which the bridge cannot carry) is refused
// here with a warning; nothing throws out of this file.
#include "cooperation/rtc/core.hpp"

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

/// A refusal made here, before the bridge: its text is this file's own, and UTF-8.
Result refused(const std::string & why) { return Result{false, rust::String::lossy(why)}; }
}  // namespace

std::shared_ptr<NodeCore> core_of(const NodeIdentity & node, std::optional<std::size_t> quota)
{
  static std::mutex mutex;
  // Keyed by the node's identity object: a key held here keeps that object's control block, so
  // no later node's identity can compare equal to a gone node's.
  static std::map<NodeIdentity, std::weak_ptr<NodeCore>, std::owner_less<NodeIdentity>> cores;
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto core = cores[node].lock()) {
    return core;
  }
  // The built-in settings are a valid configuration, so this does not throw; if it ever did,
  // the node could not run, and its constructor is where upstream's throws too.
  auto core = std::make_shared<NodeCore>(b::new_core(quota.value_or(b::default_scene_quota())));
  cores[node] = core;
  // Forget the nodes whose cores are gone, and the nodes that are gone.
  for (auto it = cores.begin(); it != cores.end();) {
    it = it->second.expired() || it->first.expired() ? cores.erase(it) : std::next(it);
  }
  return core;
}

InterfaceCore::InterfaceCore(const NodeIdentity & node, const std::string & name, bool enable_rtc)
: core_(core_of(node)), name_(name)
{
  std::string why;
  if (!utf8(name_, why)) {
    bound_ = refused("the interface name is not UTF-8: " + why);
    return;
  }
  handle_ = b::find(*core_->core, name_);
  bound_ = b::bind(*core_->core, **handle_, enable_rtc);
}

InterfaceCore::~InterfaceCore() = default;
InterfaceCore::InterfaceCore(InterfaceCore &&) noexcept = default;
InterfaceCore & InterfaceCore::operator=(InterfaceCore &&) noexcept = default;

const Result & InterfaceCore::bound() const { return bound_; }
const std::string & InterfaceCore::name() const { return name_; }

uint8_t InterfaceCore::module_type() const
{
  return bound_.ok ? b::module_type(*core_->core, **handle_) : 0;
}

Told InterfaceCore::told(Stamp now, const Result & refusal)
{
  return Told{refusal, b::advance(*core_->core, now)};
}

Told InterfaceCore::update(
  Stamp now, const Uuid & uuid, bool safe, uint8_t state, double start_distance,
  double finish_distance, bool requested, const std::optional<std::string> & sequence)
{
  if (!bound_.ok) {
    return told(now, bound_);
  }
  // The sequence is passed as it is, checked as UTF-8 without a copy.
  rust::Str stated;
  if (sequence) {
    try {
      stated = rust::Str(*sequence);
    } catch (const std::exception & e) {
      return told(now, refused(std::string("the sequence is not UTF-8: ") + e.what()));
    }
  }
  return b::update(
    *core_->core, now, **handle_, uuid, safe, state, start_distance, finish_distance, requested,
    sequence.has_value(), stated);
}

Result InterfaceCore::remove(const Uuid & uuid)
{
  if (!bound_.ok) {
    return bound_;
  }
  return b::remove(*core_->core, **handle_, uuid);
}

Result InterfaceCore::clear()
{
  return bound_.ok ? b::clear(*core_->core, **handle_) : bound_;
}

std::vector<Uuid> InterfaceCore::advance(Stamp now)
{
  const auto expired = b::advance(*core_->core, now);
  if (expired.empty()) {
    return {};
  }
  return std::vector<Uuid>(expired.begin(), expired.end());
}

#define COOPERATION_QUERY(method)                                   \
  bool InterfaceCore::method(const Uuid & uuid) const               \
  {                                                                 \
    return bound_.ok && b::method(*core_->core, **handle_, uuid);   \
  }
COOPERATION_QUERY(is_registered)
COOPERATION_QUERY(is_activated)
COOPERATION_QUERY(is_force_activated)
COOPERATION_QUERY(is_force_deactivated)
#undef COOPERATION_QUERY

std::optional<bool> InterfaceCore::is_rtc_enabled(const Uuid & uuid) const
{
  if (!bound_.ok) {
    return std::nullopt;
  }
  const auto flag = b::is_rtc_enabled(*core_->core, **handle_, uuid);
  return flag == b::Flag::Unknown ? std::nullopt : std::optional<bool>(flag == b::Flag::Yes);
}

std::optional<bool> InterfaceCore::is_terminated(const Uuid & uuid) const
{
  if (!bound_.ok) {
    return std::nullopt;
  }
  const auto flag = b::is_terminated(*core_->core, **handle_, uuid);
  return flag == b::Flag::Unknown ? std::nullopt : std::optional<bool>(flag == b::Flag::Yes);
}

void InterfaceCore::statuses_into(Stamp stamp, rust::Vec<Status> & out) const
{
  if (!bound_.ok) {
    out.clear();
    return;
  }
  b::statuses_into(*core_->core, **handle_, stamp, out);
}

rust::Vec<Status> InterfaceCore::statuses(Stamp stamp) const
{
  rust::Vec<Status> statuses;
  statuses_into(stamp, statuses);
  return statuses;
}

bool InterfaceCore::auto_mode_status() const
{
  return bound_.ok && b::auto_mode_status(*core_->core, **handle_);
}

Answered InterfaceCore::cooperate_commands(Stamp now, const std::vector<CommandIn> & commands)
{
  if (!handle_) {
    // A name the bridge cannot carry reaches no adapter: each command is refused, as the
    // adapter refuses a batch it cannot route.
    auto refusal = told(now, bound_);
    Answered answered{refusal.outcome, {}, std::move(refusal.expired)};
    for (const auto & command : commands) {
      answered.responses.push_back(CommandOut{command.uuid, command.module, false});
    }
    return answered;
  }
  return b::cooperate_commands(
    *core_->core, now, **handle_, rust::Slice<const CommandIn>(commands.data(), commands.size()));
}

Told InterfaceCore::auto_mode(Stamp now, bool enable)
{
  return bound_.ok ? b::auto_mode(*core_->core, now, **handle_, enable) : told(now, bound_);
}
}  // namespace cooperation::rtc
