#include "harness/allocator_policy.hpp"

#include <climits>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace harness {

namespace {
std::string description = "allocator defaults (policy not set)";
}

void set_freed_memory_policy(freed_memory policy) {
    if (policy == freed_memory::returned) {
        description = "allocator defaults: freed memory returned (--fresh-memory)";
        return;
    }
#if defined(__GLIBC__)
    // mallopt returns 1 on success; a sanitizer's interceptor returns something else.
    if (mallopt(M_MMAP_MAX, 0) == 1 && mallopt(M_TRIM_THRESHOLD, INT_MAX) == 1) {
        description = "glibc malloc, freed memory kept for reuse within a case (M_MMAP_MAX=0, M_TRIM_THRESHOLD=INT_MAX), returned between cases (malloc_trim)";
        return;
    }
#endif
    description = "allocator defaults: could not keep freed memory (not glibc's malloc)";
}

std::string freed_memory_policy_description() { return description; }

void return_freed_memory() {
#if defined(__GLIBC__)
    malloc_trim(0);
#endif
}

}  // namespace harness
