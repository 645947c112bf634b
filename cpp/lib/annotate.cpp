// See cooperation/rtc/annotate.hpp. Compiled with the bridge (cpp/build.rs), so that every program linking the
// Rust library has it; ThreadSanitizer's annotations are weak symbols, present only when its
// runtime is linked in.
#include "cooperation/rtc/annotate.hpp"

extern "C" {
void __tsan_acquire(void * address) __attribute__((weak));
void __tsan_release(void * address) __attribute__((weak));
}

namespace cooperation::bridge
{
void lock_acquired(std::size_t address)
{
  if (__tsan_acquire != nullptr) {
    __tsan_acquire(reinterpret_cast<void *>(address));
  }
}

void lock_releasing(std::size_t address)
{
  if (__tsan_release != nullptr) {
    __tsan_release(reinterpret_cast<void *>(address));
  }
}
}  // namespace cooperation::bridge
