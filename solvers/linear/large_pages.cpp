#include "solvers/linear/large_pages.h"

#include <SuiteSparse_config.h>
#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>

namespace cutwork::solvers {

namespace {

constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;

void* large_malloc(std::size_t bytes) {
  void* p = std::malloc(bytes);
  advise_large_pages(p, bytes);
  return p;
}

void* large_calloc(std::size_t count, std::size_t size) {
  void* p = std::calloc(count, size);
  if (p && size != 0 && count <= SIZE_MAX / size) advise_large_pages(p, count * size);
  return p;
}

void* large_realloc(void* old, std::size_t bytes) {
  void* p = std::realloc(old, bytes);
  advise_large_pages(p, bytes);
  return p;
}

}  // namespace

void advise_large_pages(void* p, std::size_t bytes) {
  if (!p || bytes < kLargePageBytes) return;
  const auto first = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t begin = (first + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t end = (first + bytes) & ~(kHugePage - 1);
  // Advice only: a kernel without transparent huge pages answers EINVAL, which changes nothing.
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

void use_large_pages_for_cholmod() {
  static const bool installed = [] {
    SuiteSparse_config.malloc_func = large_malloc;
    SuiteSparse_config.calloc_func = large_calloc;
    SuiteSparse_config.realloc_func = large_realloc;
    SuiteSparse_config.free_func = std::free;
    return true;
  }();
  (void)installed;
}

}  // namespace cutwork::solvers
