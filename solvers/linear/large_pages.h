#pragma once
/// Large arrays on transparent huge pages.
///
/// A factor of 1e5–1e6 DOFs is 0.1–1 GB that is written once per factorisation; with 4 KiB pages
/// its first touch is one page fault per 4 KiB, and on a virtual machine each fault is also a
/// fault of the host (measured on the 2-core build VM: 12 µs per 4 KiB page, 512 MB touched for
/// the first time in 1.53 s with 4 KiB pages and 0.88 s with 2 MiB pages; the second touch 18 ms).
/// Asking the kernel for huge pages (madvise(MADV_HUGEPAGE), honoured when the system's
/// transparent-huge-page mode is `madvise` or `always`) cuts the faults 512-fold and the TLB misses
/// of the memory-bound triangular solves with them. Blocks below kLargePageBytes are left alone:
/// a huge page for a small block would waste memory.
#include <cstddef>

namespace cutwork::solvers {

/// Smallest block advised (two huge pages: the aligned interior of a smaller block may be empty).
inline constexpr std::size_t kLargePageBytes = std::size_t(4) << 20;

/// Advises the 2 MiB-aligned interior of [p, p + bytes) for huge pages when bytes ≥
/// kLargePageBytes (no-op otherwise, for null p, or where the kernel refuses).
void advise_large_pages(void* p, std::size_t bytes);

/// Routes CHOLMOD's allocations (SuiteSparse_config's malloc/calloc/realloc; free is unchanged)
/// through wrappers that advise large blocks. Idempotent and thread-safe; call before
/// cholmod_start (CholmodSolver does).
void use_large_pages_for_cholmod();

}  // namespace cutwork::solvers
