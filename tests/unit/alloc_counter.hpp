#pragma once
// Counts heap allocations on this thread between start and stop (the malloc
// family is interposed in alloc_counter.cpp for the whole test binary).
namespace rigidae::test {
void start_counting_allocations();
long stop_counting_allocations();  // allocations since the start
}  // namespace rigidae::test
