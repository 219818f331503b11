// Counts calls of the malloc family on this thread while counting is on
// (Eigen allocates through std::malloc, and operator new ends there too).
//
// Normally by interposing glibc's malloc, calloc and realloc, forwarding to
// glibc's own entry points. Under AddressSanitizer the sanitizer owns the
// malloc family (interposing it too stops its runtime in its start-up
// checks), so its allocator's hook counts instead: it is called for every
// allocation ASan serves, the same calls the interposition sees.
#include "alloc_counter.hpp"

#include <cstddef>

namespace {
thread_local bool g_count_allocations = false;
thread_local long g_allocations = 0;
}  // namespace

#if defined(__SANITIZE_ADDRESS__)
// From the sanitizers' public allocator interface (clang ships it as
// <sanitizer/allocator_interface.h>; g++ 12 has the function, not the header).
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*, std::size_t),
                                                         void (*free_hook)(const volatile void*));

namespace {
void count_malloc(const volatile void*, std::size_t) {
  if (g_count_allocations) ++g_allocations;
}
void ignore_free(const volatile void*) {}
const int g_hooks_installed = __sanitizer_install_malloc_and_free_hooks(count_malloc, ignore_free);
}  // namespace
#else
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
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
#endif

namespace rigidae::test {
void start_counting_allocations() {
#if defined(__SANITIZE_ADDRESS__)
  (void)g_hooks_installed;
#endif
  g_allocations = 0;
  g_count_allocations = true;
}
long stop_counting_allocations() {
  g_count_allocations = false;
  return g_allocations;
}
}  // namespace rigidae::test
