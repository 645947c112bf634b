// The plain node's clock, logger, endpoints and timers.
#include "cooperation/rtc/node.hpp"

#include <iostream>

namespace cooperation::rtc
{
Logger::Logger(std::string node)
: node_(std::move(node)),
  sink_(std::make_shared<Sink>([](Level level, const std::string & node, const std::string & text) {
    std::cerr << (level == Level::Warn ? "[WARN] [" : "[INFO] [") << node << "]: " << text
              << '\n';
  }))
{
}

void Logger::info(const std::string & text) const { (*sink_)(Level::Info, node_, text); }
void Logger::warn(const std::string & text) const { (*sink_)(Level::Warn, node_, text); }
void Logger::set_sink(Sink sink) { *sink_ = std::move(sink); }

builtin_interfaces::msg::Time Clock::now() const
{
  const uint64_t word = now_.load(std::memory_order_acquire);
  builtin_interfaces::msg::Time time;
  time.sec = static_cast<int32_t>(static_cast<uint32_t>(word >> 32));
  time.nanosec = static_cast<uint32_t>(word);
  return time;
}

void Clock::set_now(builtin_interfaces::msg::Time now)
{
  const uint64_t seconds = static_cast<uint32_t>(now.sec);
  const uint64_t word = (seconds << 32) | static_cast<uint64_t>(now.nanosec);
  now_.store(word, std::memory_order_release);
}

Timer::Timer(std::chrono::nanoseconds period, std::function<void()> callback)
: period_(period), callback_(std::move(callback))
{
}
std::chrono::nanoseconds Timer::period() const { return period_; }
void Timer::fire() const { callback_(); }

Node::Node(std::string name)
: name_(std::move(name)),
  logger_(name_),
  clock_(std::make_shared<Clock>()),
  base_(std::make_shared<NodeBase>(NodeBase{name_}))
{
}

const std::string & Node::get_name() const { return name_; }
builtin_interfaces::msg::Time Node::now() const { return clock_->now(); }
void Node::set_now(builtin_interfaces::msg::Time now) { clock_->set_now(now); }
Clock::SharedPtr Node::get_clock() const { return clock_; }
std::shared_ptr<NodeBase> Node::get_node_base_interface() const { return base_; }

Logger & Node::get_logger() { return logger_; }

Timer::SharedPtr Node::create_wall_timer(
  std::chrono::nanoseconds period, std::function<void()> callback)
{
  auto timer = std::make_shared<Timer>(period, std::move(callback));
  const std::lock_guard<std::mutex> lock(mutex_);
  timers_.push_back(timer);
  return timer;
}

void Node::fire_timers()
{
  std::vector<Timer::SharedPtr> live;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto & timer : timers_) {
      if (auto held = timer.lock()) {
        live.push_back(held);
      }
    }
  }
  for (const auto & timer : live) {
    timer->fire();
  }
}

void Node::remember(const std::string & name, std::type_index type, std::shared_ptr<void> handle)
{
  const std::lock_guard<std::mutex> lock(mutex_);
  endpoints_.insert_or_assign(name, Endpoint{type, handle});
}
}  // namespace cooperation::rtc
