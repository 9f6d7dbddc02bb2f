// The harness's allocator policy (harness/allocator_policy.hpp): under `kept`, memory a timed
// round frees stays in the process for the next round and is given back between cases; the
// run's sidecar names the policy; `--fresh-memory` selects glibc's defaults on run and scene.

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include <malloc.h>
#include <unistd.h>

#include "harness/allocator_policy.hpp"
#include "harness/command_line.hpp"
#include "harness/run_info.hpp"

namespace {

// Resident bytes of this process (/proc/self/statm's second field, in pages).
long resident_bytes() {
    std::ifstream statm("/proc/self/statm");
    long size = 0, resident = 0;
    statm >> size >> resident;
    return resident * sysconf(_SC_PAGESIZE);
}

constexpr std::size_t block_bytes = std::size_t(64) << 20;
// The block escapes through here, so the compiler cannot drop the malloc, memset and free.
void* volatile escaped_block = nullptr;

TEST(allocator_policy, a_freed_large_block_stays_in_the_process_until_returned) {
    harness::set_freed_memory_policy(harness::freed_memory::kept);
    if (harness::freed_memory_policy_description().find("could not") != std::string::npos)
        GTEST_SKIP() << "not glibc's malloc (a sanitizer's): " << harness::freed_memory_policy_description();
    void* block = std::malloc(block_bytes);
    ASSERT_NE(block, nullptr);
    std::memset(block, 1, block_bytes);
    escaped_block = block;
    std::free(escaped_block);
    // With glibc's defaults a 64 MiB block is an mmap, unmapped by free: nothing stays free in
    // the arena. Kept, the whole block is free memory of the heap.
    EXPECT_GE(mallinfo2().fordblks, block_bytes);
    const long before = resident_bytes();
    harness::return_freed_memory();
    EXPECT_GE(before - resident_bytes(), static_cast<long>(block_bytes / 2))
        << "malloc_trim gave back less than half of the freed block";
}

TEST(allocator_policy, the_run_sidecar_names_the_policy) {
    harness::set_freed_memory_policy(harness::freed_memory::returned);
    const auto dir = std::filesystem::temp_directory_path() / ("allocator_policy_test_" + std::to_string(getpid()));
    harness::write_run_sidecar(dir, harness::run_info{"policy-run", "knn", "smoke", {}, {}, {}}, 1.0);
    std::ifstream in(dir / "runs" / "policy-run.json");
    const auto sidecar = nlohmann::json::parse(in);
    EXPECT_EQ(sidecar.at("allocator").get<std::string>(), harness::freed_memory_policy_description());
    EXPECT_NE(sidecar.at("allocator").get<std::string>().find("--fresh-memory"), std::string::npos);
    std::filesystem::remove_all(dir);
}

TEST(allocator_policy, fresh_memory_is_an_option_of_run_and_scene_and_off_by_default) {
    harness::command_line_vocabulary vocabulary;
    vocabulary.runnable_suites.push_back({"knn", "k-nearest"});
    const std::string scene = std::string(SPATIAL_SOURCE_DIR) + "/datasets/scenes/falling_boxes.toml";
    {
        harness::command_line cli(vocabulary);
        const char* argv[] = {"spatialbench", "run", "--suite", "knn"};
        cli.parse(4, argv);
        EXPECT_FALSE(cli.run.fresh_memory);
    }
    {
        harness::command_line cli(vocabulary);
        const char* argv[] = {"spatialbench", "run", "--suite", "knn", "--fresh-memory"};
        cli.parse(5, argv);
        EXPECT_TRUE(cli.run.fresh_memory);
    }
    {
        harness::command_line cli(vocabulary);
        const char* argv[] = {"spatialbench", "scene", scene.c_str(), "--fresh-memory"};
        cli.parse(4, argv);
        EXPECT_TRUE(cli.scene.fresh_memory);
    }
}

}  // namespace
