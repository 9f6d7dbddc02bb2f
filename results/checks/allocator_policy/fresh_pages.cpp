// What a fresh page costs on this machine: five rounds, each allocating 100 MB, filling it and
// freeing it. With glibc's defaults the block is a fresh mmap every round (page faults each
// time); with freed memory kept (the harness's policy, harness/allocator_policy.hpp) only the
// first round faults. Throwaway check, not built by CMake:
//   g++ -O2 fresh_pages.cpp -o fresh_pages && ./fresh_pages
//   GLIBC_TUNABLES=glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=4294967295 ./fresh_pages
#include <chrono>
#include <cstdio>
#include <vector>

int main() {
    for (int round = 0; round < 5; ++round) {
        const auto t0 = std::chrono::steady_clock::now();
        {
            std::vector<double> block(12'500'000, 1.0);
            asm volatile("" ::"r"(block.data()) : "memory");  // keep the fill
        }
        const auto t1 = std::chrono::steady_clock::now();
        std::printf("round %d: %.1f ms\n", round, std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
}
