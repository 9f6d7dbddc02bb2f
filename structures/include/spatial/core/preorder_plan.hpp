#pragma once
// spatial::detail::preorder_plan<Record> — the split records of a tree build planned on
// several threads (bvh::rebuild(par), kd_tree::insert(first, last, par)), put back into the
// preorder in which the sequential builder makes its nodes.
//
// Each planner appends chunks, each chunk the preorder of a whole subtree or a single node;
// a record names its range of items [begin, begin + count). The ranges of one partition tree
// nest, so ordering the chunks by their first record's (begin ascending, count descending)
// and concatenating them gives the preorder of the whole tree without sorting the records
// themselves: O(c log c) for c chunks.

#include <algorithm>
#include <mutex>
#include <utility>
#include <vector>

namespace spatial::detail {

template <class Record>
struct preorder_plan {
    std::mutex mutex;
    std::vector<std::vector<Record>> chunks;

    // Safe to call from concurrent planners; an empty chunk is dropped.
    void append(std::vector<Record>&& local) {
        if (local.empty()) return;
        const std::lock_guard<std::mutex> lock(mutex);
        chunks.push_back(std::move(local));
    }
    void sort_to_preorder() {
        std::sort(chunks.begin(), chunks.end(), [](const auto& a, const auto& b) {
            return a.front().begin != b.front().begin ? a.front().begin < b.front().begin
                                                      : a.front().count > b.front().count;
        });
    }
};

}  // namespace spatial::detail
