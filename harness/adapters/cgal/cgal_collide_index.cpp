// CGAL box_intersection_d behind harness::collide_index (declared in
// harness/collide_adapters.hpp).
//
// CGAL's algorithm (Zomorodian and Edelsbrunner, "Fast software for box intersections",
// SoCG 2000) is a streamed segment tree: it sorts and partitions the two sequences it is
// given IN PLACE, recursing on the dimensions, down to a cutoff where it scans. It keeps no
// structure between calls, so build() and update() only refresh our sequence and every query
// is a full O(n log^3 n + k) run (box_self_intersection_d additionally copies the sequence
// once per call, because it intersects the range with a copy of itself).
//
// Identity: Box_with_handle_d<double, 3, const collide_box*> with the default ID_FROM_HANDLE
// policy takes the id from the handle's target address. The handle points into our own copy
// of the boxes, so the id (a) survives CGAL's reordering and copying of the sequence (the
// ID_FROM_BOX_ADDRESS policy would not: CGAL's internal copy would give the same box a second
// id and self-pairs (a, a')), (b) differs between the built set and `others`, and (c) maps
// back to the index by pointer arithmetic.
//
// Cutoff (setting `cutoff`, a positive count): below it a block of boxes is scanned pairwise
// instead of split further. CGAL's default is 10, the registry's; the tuning sweep
// (harness/tuning_sweep.hpp) runs larger ones, which trade the segment tree's recursion for
// scanning.
//
// Closedness: we pass Box_intersection_d::CLOSED explicitly (it is also CGAL's default):
// boxes sharing only a face, edge or corner intersect, zero-extent boxes take part. CGAL
// compares the doubles exactly, so its answer is the closed-box answer with no filtering;
// only the caller's exact test runs on the pairs found.

#include <CGAL/Bbox_3.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harness/collide_adapters.hpp"
#include "harness/tuning_sweep.hpp"

namespace harness {
namespace {

using cgal_box = CGAL::Box_intersection_d::Box_with_handle_d<double, 3, const collide_box*>;

CGAL::Bbox_3 bbox_of(const collide_box& b) {
    return {b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]};
}

class cgal_collide_index final : public collide_index {
public:
    explicit cgal_collide_index(std::ptrdiff_t cutoff) : cutoff_(cutoff) {}
    std::string name() const override { return "cgal_box_intersection"; }

    void build(std::span<const collide_box> boxes) override {
        boxes_.assign(boxes.begin(), boxes.end());
        sequence_.clear();
        sequence_.reserve(boxes_.size());
        for (const collide_box& b : boxes_) sequence_.emplace_back(bbox_of(b), &b);
    }

    void update(std::span<const collide_box> boxes) override {
        if (boxes.size() != boxes_.size())
            throw std::invalid_argument("cgal_box_intersection: update() needs the built boxes' count");
        // Same size: no reallocation, so the handles stay valid. The sequence is in whatever
        // order the last query left it; each entry is refreshed from its own handle.
        std::copy(boxes.begin(), boxes.end(), boxes_.begin());
        for (cgal_box& b : sequence_) b = cgal_box(bbox_of(*b.handle()), b.handle());
    }

    std::vector<index_pair> self_pairs(const exact_test& exact) override {
        std::vector<index_pair> out;
        if (sequence_.size() < 2) return out;
        const collide_box* base = boxes_.data();
        auto report = [&](const cgal_box& a, const cgal_box& b) {
            auto i = static_cast<std::uint32_t>(a.handle() - base);
            auto j = static_cast<std::uint32_t>(b.handle() - base);
            if (i > j) std::swap(i, j);
            if (exact && !exact(i, j)) return;
            out.emplace_back(i, j);
        };
        CGAL::box_self_intersection_d(sequence_.begin(), sequence_.end(), report, cutoff_,
                                      CGAL::Box_intersection_d::CLOSED);
        sort_unique_pairs(out);
        return out;
    }

    std::vector<index_pair> pairs_with(std::span<const collide_box> others, const exact_test& exact) override {
        std::vector<index_pair> out;
        if (sequence_.empty() || others.empty()) return out;
        std::vector<cgal_box> other_sequence;
        other_sequence.reserve(others.size());
        for (const collide_box& b : others) other_sequence.emplace_back(bbox_of(b), &b);
        const collide_box* base = boxes_.data();
        const collide_box* other_base = others.data();
        auto report = [&](const cgal_box& a, const cgal_box& b) {
            // CGAL passes the box of the first range first; the address test costs nothing and
            // does not depend on that.
            const bool a_is_ours = a.handle() >= base && a.handle() < base + boxes_.size();
            const cgal_box& ours = a_is_ours ? a : b;
            const cgal_box& theirs = a_is_ours ? b : a;
            const auto i = static_cast<std::uint32_t>(ours.handle() - base);
            const auto j = static_cast<std::uint32_t>(theirs.handle() - other_base);
            if (exact && !exact(i, j)) return;
            out.emplace_back(i, j);
        };
        CGAL::box_intersection_d(sequence_.begin(), sequence_.end(), other_sequence.begin(), other_sequence.end(),
                                 report, cutoff_, CGAL::Box_intersection_d::CLOSED);
        sort_unique_pairs(out);
        return out;
    }

    std::size_t memory_bytes() const override {
        return sizeof(*this) + boxes_.capacity() * sizeof(collide_box) + sequence_.capacity() * sizeof(cgal_box);
    }

private:
    std::ptrdiff_t cutoff_;
    std::vector<collide_box> boxes_;  // our copy: the handles point here
    std::vector<cgal_box> sequence_;  // CGAL's working sequence, reordered by every query
};

}  // namespace

std::unique_ptr<collide_index> make_cgal_box_intersection_collide_index(const key_values& settings) {
    const std::size_t cutoff = count_setting(settings, "cutoff", "cgal_box_intersection");
    if (cutoff > static_cast<std::size_t>(std::numeric_limits<std::ptrdiff_t>::max()))
        throw std::invalid_argument("cgal_box_intersection: setting cutoff=" + std::to_string(cutoff) +
                                    " is too large");
    return std::make_unique<cgal_collide_index>(static_cast<std::ptrdiff_t>(cutoff));
}

}  // namespace harness
