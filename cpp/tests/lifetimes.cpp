// Destruction orders: an interface that outlives its node keeps working on what it kept (the
// clock, the logger, the core), and a node made where a gone node was is another node, with a
// core of its own. Run under AddressSanitizer by tools/cpp.
#include "check.hpp"

#include <memory>
#include <new>

using autoware::rtc_interface::RTCInterface;
using autoware::rtc_interface::State;
using cooperation::rtc::Node;

namespace
{
void interface_outlives_its_node()
{
  auto node = std::make_unique<Node>("planner");
  check::Log log(*node);
  node->set_now(check::at(5));
  RTCInterface rtc(node.get(), "intersection", true);
  const auto id = check::uuid(1);
  rtc.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 10.0, 10.0, check::at(5));
  rtc.removeExpiredCooperateStatus();  // the core's time: 5 s
  const auto clock = node->get_clock();
  node.reset();
  // Every call that read the node reads what the interface kept.
  for (int32_t second = 6; second <= 30; ++second) {
    clock->set_now(check::at(second));
    rtc.removeExpiredCooperateStatus();
  }
  CHECK(!rtc.isRegistered(id), "the scene expired on the kept clock");
  rtc.print();
  rtc.updateCooperateStatus(id, true, State::RUNNING, 10.0, 10.0, check::at(30));
  CHECK(log.warned("refused"), "a refusal after the node is gone is still logged, to its sink");
  rtc.publishCooperateStatus(check::at(30));
}

void a_node_where_a_gone_one_was_is_another()
{
  alignas(Node) unsigned char storage[sizeof(Node)];
  auto * first = new (storage) Node("first");
  auto early = std::make_unique<RTCInterface>(first, "intersection", true);
  const auto id = check::uuid(2);
  early->updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 10.0, 10.0, check::at(0));
  first->~Node();
  auto * second = new (storage) Node("second");
  CHECK(static_cast<void *>(second) == static_cast<void *>(storage), "the same address");
  autoware::rtc_interface::BasicRTCInterface<> late(second, "crosswalk", true);  // the default node
  late.updateCooperateStatus(id, true, State::WAITING_FOR_EXECUTION, 20.0, 20.0, check::at(0));
  CHECK(late.isRegistered(id), "the new node's core does not hold the gone node's scene");
  CHECK(early->isRegistered(id), "the gone node's interface keeps its own core");
  early.reset();
  second->~Node();
}
}  // namespace

int main()
{
  interface_outlives_its_node();
  a_node_where_a_gone_one_was_is_another();
  return check::report("lifetimes");
}
