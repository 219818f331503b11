// Interposes glibc's malloc family (Eigen allocates through std::malloc and
// operator new ends there too), forwarding to glibc's own entry points, and
// counts calls on this thread while counting is on.
#include "alloc_counter.hpp"

#include <cstddef>

extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
namespace {
thread_local bool g_count_allocations = false;
thread_local long g_allocations = 0;
}  // namespace
extern "C" void* malloc(std::size_t n) {
  if (g_count_allocations) ++g_allocations;
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t n, std::size_t size) {
  if (g_count_allocations) ++g_allocations;
  return __libc_calloc(n, size);
}
extern "C" void* realloc(void* p, std::size_t n) {
  if (g_count_allocations) ++g_allocations;
  return __libc_realloc(p, n);
}

namespace rigidae::test {
void start_counting_allocations() {
  g_allocations = 0;
  g_count_allocations = true;
}
long stop_counting_allocations() {
  g_count_allocations = false;
  return g_allocations;
}
}  // namespace rigidae::test
