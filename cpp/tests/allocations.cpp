// A planning cycle through the C++ class allocates nothing once it has run at its size, as the
// Rust core's cycle does (`tests/allocations.rs`): every module's queries, its updates, the
// expiry and the publication, with the node's clock moving. The count is the process's own:
// `malloc` and its kin are wrapped here, so the Rust half (through the C library's allocator)
// and the C++ half are both counted. Not built under a sanitizer, which wraps them itself.
#include "check.hpp"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>

using autoware::rtc_interface::RTCInterface;
using autoware::rtc_interface::State;
using cooperation::rtc::Node;

extern "C" {
void * __libc_malloc(std::size_t size);
void * __libc_calloc(std::size_t count, std::size_t size);
void * __libc_realloc(void * pointer, std::size_t size);
void * __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void * pointer);
}

namespace
{
std::atomic<long> allocations{0};
}

extern "C" {
void * malloc(std::size_t size)
{
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void * calloc(std::size_t count, std::size_t size)
{
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, size);
}
void * realloc(void * pointer, std::size_t size)
{
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(pointer, size);
}
void * aligned_alloc(std::size_t alignment, std::size_t size)
{
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
void * memalign(std::size_t alignment, std::size_t size)
{
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, size);
}
int posix_memalign(void ** out, std::size_t alignment, std::size_t size)
{
  allocations.fetch_add(1, std::memory_order_relaxed);
  void * pointer = __libc_memalign(alignment, size);
  if (pointer == nullptr) {
    return 12;  // ENOMEM
  }
  *out = pointer;
  return 0;
}
void free(void * pointer) { __libc_free(pointer); }
}

namespace
{
/// The allocations of `cycles` planning cycles of `scenes` scenes in one interface, after three
/// cycles to grow the buffers; the clock moves 100 ms a cycle.
long allocations_per_cycles(unsigned scenes, int cycles)
{
  Node node("allocations");
  RTCInterface rtc(&node, "intersection", false);
  int64_t ms = 0;
  const auto cycle = [&] {
    ms += 100;
    node.set_now(check::at(
      static_cast<int32_t>(ms / 1000), static_cast<uint32_t>(ms % 1000) * 1000000U));
    bool activated = false;
    for (unsigned i = 0; i < scenes; ++i) {
      activated = rtc.isActivated(check::uuid(i)) != activated;
      activated = rtc.isRTCEnabled(check::uuid(i)) != activated;
    }
    for (unsigned i = 0; i < scenes; ++i) {
      rtc.updateCooperateStatus(
        check::uuid(i), true, State::WAITING_FOR_EXECUTION, 10.0 + i, 20.0 + i, node.now());
    }
    rtc.removeExpiredCooperateStatus();
    rtc.publishCooperateStatus(node.now());
    return activated;
  };
  for (int warm = 0; warm < 3; ++warm) {
    cycle();
  }
  const long before = allocations.load();
  for (int i = 0; i < cycles; ++i) {
    cycle();
  }
  return allocations.load() - before;
}
}  // namespace

int main()
{
  // The wrapping counts: a plain allocation is seen.
  const long before = allocations.load();
  auto * probe = new std::string(64, 'x');
  check::that(allocations.load() > before, "an allocation is counted", __FILE__, __LINE__);
  delete probe;

  for (const unsigned scenes : {1U, 3U, 10U, 16U, 17U, 100U}) {
    const long counted = allocations_per_cycles(scenes, 20);
    check::that(
      counted == 0,
      std::to_string(scenes) + " scenes: " + std::to_string(counted) + " allocations in 20 cycles",
      __FILE__, __LINE__);
  }
  return check::report("allocations");
}
