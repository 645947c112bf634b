// A node for a build without ROS 2: what `BasicRTCInterface` needs of `rclcpp::Node` (a clock,
// a logger, publishers, services and timers), in process. A planner sets its clock and runs its
// timers; an operator tool or a test in the same process reads what was published and calls
// the services. With rclcpp, `RTCInterface` is built on `rclcpp::Node` instead.
#ifndef COOPERATION__RTC__NODE_HPP_
#define COOPERATION__RTC__NODE_HPP_

#include "cooperation/rtc/messages.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <typeindex>
#include <utility>
#include <vector>

namespace cooperation::rtc
{
/// Where a node's log lines go: a sink the owner sets (standard error by default).
class Logger
{
public:
  enum class Level { Info, Warn };
  using Sink = std::function<void(Level, const std::string & node, const std::string & text)>;

  explicit Logger(std::string node);
  void info(const std::string & text) const;
  void warn(const std::string & text) const;
  /// Sends the lines to `sink` from now on, this logger's and its copies' (an interface keeps a
  /// copy, so it may outlive its node).
  void set_sink(Sink sink);

private:
  std::string node_;
  std::shared_ptr<Sink> sink_;
};

/// A node's clock: the time its owner last set (`rclcpp::Clock`'s `now()`). An interface keeps
/// it, so it may outlive its node. Reading it takes no lock: every update and expiry of every
/// interface reads it.
class Clock
{
public:
  using SharedPtr = std::shared_ptr<Clock>;
  builtin_interfaces::msg::Time now() const;
  void set_now(builtin_interfaces::msg::Time now);

private:
  /// The time as one word, its seconds' bits above its nanoseconds', so that a reader sees one
  /// time set, never half of two.
  std::atomic<uint64_t> now_{0};
};

/// What identifies a node (`rclcpp::node_interfaces::NodeBaseInterface`'s role): its name.
struct NodeBase
{
  std::string name;
};

/// The latest message published on a topic; the depth is 1, as upstream's.
template <class Message>
class Publisher
{
public:
  using SharedPtr = std::shared_ptr<Publisher>;
  void publish(const Message & message)
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    latest_ = message;
    ++count_;
  }
  std::optional<Message> latest() const
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    return latest_;
  }
  std::size_t count() const
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    return count_;
  }

private:
  mutable std::mutex mutex_;
  std::optional<Message> latest_;
  std::size_t count_ = 0;
};

/// A service: its callback, called by `Node::call`.
template <class Service>
class ServiceServer
{
public:
  using SharedPtr = std::shared_ptr<ServiceServer>;
  using Callback = std::function<void(
    const typename Service::Request::SharedPtr, typename Service::Response::SharedPtr)>;
  explicit ServiceServer(Callback callback) : callback_(std::move(callback)) {}
  typename Service::Response call(const typename Service::Request & request) const
  {
    auto response = std::make_shared<typename Service::Response>();
    callback_(std::make_shared<typename Service::Request>(request), response);
    return *response;
  }

private:
  Callback callback_;
};

/// A timer: its period and callback, run by `Node::fire_timers`.
class Timer
{
public:
  using SharedPtr = std::shared_ptr<Timer>;
  Timer(std::chrono::nanoseconds period, std::function<void()> callback);
  std::chrono::nanoseconds period() const;
  void fire() const;

private:
  std::chrono::nanoseconds period_;
  std::function<void()> callback_;
};

/// A planning node without ROS 2.
class Node
{
public:
  explicit Node(std::string name);

  const std::string & get_name() const;
  /// The node's clock: the time it was last set to.
  builtin_interfaces::msg::Time now() const;
  /// Sets the node's clock (the planner's time source: a simulator, a bag, the system clock).
  void set_now(builtin_interfaces::msg::Time now);
  /// The clock itself, to keep.
  Clock::SharedPtr get_clock() const;
  /// What identifies the node (`cooperation::rtc::identity_of`).
  std::shared_ptr<NodeBase> get_node_base_interface() const;
  Logger & get_logger();

  template <class Message>
  typename Publisher<Message>::SharedPtr create_publisher(const std::string & topic, std::size_t)
  {
    auto publisher = std::make_shared<Publisher<Message>>();
    remember(topic, typeid(Message), publisher);
    return publisher;
  }

  template <class Service>
  typename ServiceServer<Service>::SharedPtr create_service(
    const std::string & name, typename ServiceServer<Service>::Callback callback)
  {
    auto server = std::make_shared<ServiceServer<Service>>(std::move(callback));
    remember(name, typeid(Service), server);
    return server;
  }

  Timer::SharedPtr create_wall_timer(
    std::chrono::nanoseconds period, std::function<void()> callback);

  /// The latest message on `topic`, if one was published there with this type.
  template <class Message>
  std::optional<Message> latest(const std::string & topic) const
  {
    auto publisher = find<Publisher<Message>>(topic, typeid(Message));
    return publisher ? publisher->latest() : std::nullopt;
  }

  /// Calls the service `name`; no answer if the node has no such service of this type.
  template <class Service>
  std::optional<typename Service::Response> call(
    const std::string & name, const typename Service::Request & request) const
  {
    auto server = find<ServiceServer<Service>>(name, typeid(Service));
    return server ? std::optional(server->call(request)) : std::nullopt;
  }

  /// Runs every live timer's callback once.
  void fire_timers();

private:
  struct Endpoint
  {
    std::type_index type;
    std::weak_ptr<void> handle;
  };
  void remember(const std::string & name, std::type_index type, std::shared_ptr<void> handle);
  template <class Handle>
  std::shared_ptr<Handle> find(const std::string & name, std::type_index type) const
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto it = endpoints_.find(name);
    if (it == endpoints_.end() || it->second.type != type) {
      return nullptr;
    }
    return std::static_pointer_cast<Handle>(it->second.handle.lock());
  }

  std::string name_;
  Logger logger_;
  Clock::SharedPtr clock_;
  std::shared_ptr<NodeBase> base_;
  mutable std::mutex mutex_;
  std::map<std::string, Endpoint> endpoints_;
  std::vector<std::weak_ptr<Timer>> timers_;
};
}  // namespace cooperation::rtc

#endif  // COOPERATION__RTC__NODE_HPP_
