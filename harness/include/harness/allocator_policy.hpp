#pragma once
// harness::keep_freed_memory — what the harness's process does with the memory a timed round
// frees, so that the next round measures the structure, not the kernel's page faults.
//
// Why: glibc's malloc serves large blocks (from 128 KiB, its threshold rising to 32 MiB) with a
// fresh mmap() each and unmaps them on free, while small blocks come from its heap and are
// reused. A bulk build allocates a few large arrays; a loop of insertions grows many small
// blocks. So every timed round of a bulk path touched fresh pages, and a loop mostly did not.
// On a VM where a fresh 4 KiB page costs ~14 us (a 2-core EPYC, 2026-11: 100 MB of fresh pages
// filled in 360 ms, the same 100 MB reused in 5 ms) the bulk-against-loop ratios measured the
// hypervisor: uniform_grid's bulk build read 197 ns a point with fresh pages, 47 ns reused.
//
// Policy `kept` (the default of `run` and `scene`): every block comes from the heap
// (M_MMAP_MAX = 0) and free never shrinks it (M_TRIM_THRESHOLD = INT_MAX), so a round reuses
// what the previous round freed (jemalloc and tcmalloc also keep freed pages for reuse rather
// than unmapping each block, releasing them later). The first round still touches fresh
// pages; the bulk-against-loop comparisons make it an untimed warm-up.
// Between cases the harness returns what is free (return_freed_memory, malloc_trim), so one
// case's freed memory is neither held through the next nor taken for memory in use.
// Policy `returned` (`--fresh-memory`): glibc's defaults, cold allocation costs included.
//
// Neither policy reaches memory a library maps itself: Embree's BVH allocator can map its
// blocks directly (FastAllocator's os_malloc path), and pays fresh pages under both. Where
// the allocator is not glibc's (a sanitizer's) the policy cannot be set, and says so.

#include <string>

namespace harness {

enum class freed_memory { kept, returned };

// Sets the process's policy; call before anything is measured.
void set_freed_memory_policy(freed_memory policy);
// The policy in effect, for the run's sidecar ("allocator").
std::string freed_memory_policy_description();
// Gives the free memory the process holds back to the system (a no-op where nothing is held).
void return_freed_memory();

}  // namespace harness
