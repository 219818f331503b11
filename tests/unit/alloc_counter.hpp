#pragma once
// Counts heap allocations on this thread between start and stop (the malloc
// family interposed for the whole test binary, or AddressSanitizer's
// allocator hook in a sanitized build: alloc_counter.cpp).
namespace rigidae::test {
void start_counting_allocations();
long stop_counting_allocations();  // allocations since the start
}  // namespace rigidae::test
