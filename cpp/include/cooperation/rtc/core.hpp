// The verified core, one per node, as the C++ class sees it. Every call is one call of
// `cooperation_adapters::rtc` on the node's shared core, behind its one lock; nothing here decides
// anything. The values that cross are the bridge's own structs (`cooperation::bridge`, declared
// once in `cpp/src/bridge.rs` and generated for C++ by cxx), so nothing is converted between
// here and the adapter. Nothing here throws, either: a refusal comes back as a `Result`
// carrying the core's explanation.
#ifndef COOPERATION__RTC__CORE_HPP_
#define COOPERATION__RTC__CORE_HPP_

#include "cooperation-cpp/src/bridge.rs.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace cooperation::rtc
{
/// A scene's identifier: `unique_identifier_msgs/UUID`'s 16 bytes (`bytes`).
using Uuid = ::cooperation::bridge::Uuid;
/// A time: `builtin_interfaces/Time`'s fields.
using Stamp = ::cooperation::bridge::Stamp;
/// What a call that changes the core did: `ok`, or the core's explanation in `warning`.
using Result = ::cooperation::bridge::Outcome;
/// One status as `publishCooperateStatus` sends it, its constants as their numbers.
using Status = ::cooperation::bridge::Status;
/// One operator command of a `CooperateCommands` request.
using CommandIn = ::cooperation::bridge::CommandIn;
/// One entry of a `CooperateCommands` response.
using CommandOut = ::cooperation::bridge::CommandOut;
/// A `CooperateCommands` call's outcome, the adapter's response entries, and the scenes that
/// expired before the call.
using Answered = ::cooperation::bridge::Answered;
/// What a call made at the node's time did (`outcome`), and the scenes that expired before it
/// (`expired`).
using Told = ::cooperation::bridge::Told;

class NodeCore;

/// A node's identity: the object its node base interface is (`get_node_base_interface()`, as
/// `rclcpp::Node` has), held weakly. Two identities are the same node when they share that
/// object; a node made after another is gone is another node, wherever it is allocated.
using NodeIdentity = std::weak_ptr<const void>;

/// The identity of `node`.
template <class NodeT>
NodeIdentity identity_of(NodeT * node)
{
  return NodeIdentity(std::shared_ptr<const void>(node->get_node_base_interface()));
}

/// The core of the node `node` is, shared by every interface made with the same node, in
/// whichever plugin of the process (made at the first request, and dropped with the last
/// interface that holds it), built as every node of this project builds its core: the built-in
/// settings' policies and limits. `quota`, the most live scenes one interface may hold (0: none;
/// by default the nodes' own default), applies when the core is made.
std::shared_ptr<NodeCore> core_of(
  const NodeIdentity & node, std::optional<std::size_t> quota = std::nullopt);

/// `core_of(identity_of(node), quota)`.
template <class NodeT>
std::shared_ptr<NodeCore> core_of(NodeT * node, std::optional<std::size_t> quota = std::nullopt)
{
  return core_of(identity_of(node), quota);
}

/// One RTC interface of a node's core: upstream's calls, each one call on the core.
class InterfaceCore
{
public:
  /// The interface `name` of the core of `node`, its modules' policy set as upstream's
  /// `enable_rtc` says (required when true). A name with no binding makes an interface that
  /// answers every query `false` and refuses every change; `bound()` says why.
  InterfaceCore(const NodeIdentity & node, const std::string & name, bool enable_rtc);
  ~InterfaceCore();
  InterfaceCore(const InterfaceCore &) = delete;
  InterfaceCore & operator=(const InterfaceCore &) = delete;
  InterfaceCore(InterfaceCore &&) noexcept;
  InterfaceCore & operator=(InterfaceCore &&) noexcept;

  /// Whether the name is bound, and why not.
  const Result & bound() const;
  /// The interface's name.
  const std::string & name() const;
  /// The module type its statuses carry (`Module::NONE` if it is not bound).
  uint8_t module_type() const;

  /// `updateCooperateStatus` made at the node clock's `now`, the scene's sequence stated when
  /// `sequence` is given. The core is told `now` first, in the same call
  /// (`[COOP-ENGINE-TIME.1]`), refused or not.
  Told update(
    Stamp now, const Uuid & uuid, bool safe, uint8_t state, double start_distance,
    double finish_distance, bool requested,
    const std::optional<std::string> & sequence = std::nullopt);
  /// `removeCooperateStatus`.
  Result remove(const Uuid & uuid);
  /// `clearCooperateStatus`.
  Result clear();
  /// Tells the node's core that its clock reads `now`; the scenes that expired. Time passes once
  /// however many interfaces of the node tell it the same reading.
  std::vector<Uuid> advance(Stamp now);

  bool is_registered(const Uuid & uuid) const;
  bool is_activated(const Uuid & uuid) const;
  bool is_force_activated(const Uuid & uuid) const;
  bool is_force_deactivated(const Uuid & uuid) const;
  /// No answer for a scene that is not live (`[COOP-DEV-UNKNOWN-QUERY.1]`).
  std::optional<bool> is_rtc_enabled(const Uuid & uuid) const;
  /// No answer for a scene this interface never registered, or that the core forgot.
  std::optional<bool> is_terminated(const Uuid & uuid) const;

  /// The interface's live scenes, in identifier order, each stamped with its last report.
  rust::Vec<Status> statuses(Stamp stamp) const;
  /// `statuses`, written over `out`, which allocates only when it has too little capacity.
  void statuses_into(Stamp stamp, rust::Vec<Status> & out) const;
  /// The interface's auto-mode status.
  bool auto_mode_status() const;

  /// The interface's `CooperateCommands` service, called at the node clock's `now` (told first,
  /// in the same call): the batch applies whole or not at all; the response's entries are the
  /// adapter's (for a name that is not bound, each refused).
  Answered cooperate_commands(Stamp now, const std::vector<CommandIn> & commands);
  /// The interface's `AutoMode` service, called at the node clock's `now` (told first, in the
  /// same call).
  Told auto_mode(Stamp now, bool enable);

private:
  /// `refusal`, made at `now`: the core is still told the time.
  Told told(Stamp now, const Result & refusal);

  std::shared_ptr<NodeCore> core_;
  std::string name_;
  /// The interface, found by name once; none when the name is not UTF-8.
  std::optional<rust::Box<::cooperation::bridge::Handle>> handle_;
  Result bound_;
};
}  // namespace cooperation::rtc

#endif  // COOPERATION__RTC__CORE_HPP_
