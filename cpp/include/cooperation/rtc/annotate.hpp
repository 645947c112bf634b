// Tells ThreadSanitizer about the core's lock. The lock is Rust's (`cooperation_adapters::Shared`),
// which ThreadSanitizer cannot see, so without this it would take the core's own copies and
// allocations under that lock, by two threads, for a race. The bridge calls these just after it
// takes the lock and just before it lets go; they do nothing unless the program is linked with
// ThreadSanitizer's runtime.
#ifndef COOPERATION__RTC__ANNOTATE_HPP_
#define COOPERATION__RTC__ANNOTATE_HPP_

#include <cstddef>

namespace cooperation::bridge
{
/// The lock of the core at `address` was just taken.
void lock_acquired(std::size_t address);
/// The lock of the core at `address` is about to be let go.
void lock_releasing(std::size_t address);
}  // namespace cooperation::bridge

#endif  // COOPERATION__RTC__ANNOTATE_HPP_
