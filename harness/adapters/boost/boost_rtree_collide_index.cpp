// Boost.Geometry's rtree (Debian's libboost-dev 1.74, header-only) behind
// harness::collide_index (declared in harness/collide_adapters.hpp): the collide suite's
// boost_rtree_collide. The kNN peers over the same library are boost_rtree_adapter.cpp.
//
// The tree: bgi::rstar<16>, the R*-tree of Beckmann, Kriegel, Schneider and Seeger (SIGMOD
// 1990), bulk-loaded by the rtree's packing constructor (Boost's top-down packing in the
// spirit of Leutenegger, Lopez and Edgington's Sort-Tile-Recursive, ICDE 1997), as the kNN
// peer boost_rtree. The node capacity is a template argument: one configuration, no sweep.
// Values are (box, index) pairs, so a query reads the box from the leaf, with no indirection.
//
// Queries, as a Boost user would write them:
//   self_pairs()  one query(bgi::intersects(box i)) per built box, keeping the found j > i:
//                 each pair once, (i, j) with i < j (a box finds itself; it is skipped).
//   pairs_with()  one query per box j of `others`, reporting each found i as (i, j).
// Found values stream into a function output iterator: no per-query vector.
//
// Closedness: Boost's box/box intersects is "not disjoint", and its box/box disjoint is
// max < min on some axis (boost/geometry/algorithms/detail/disjoint/box_box.hpp), evaluated
// on the doubles exactly, at the nodes and at the values alike. So boxes touching on a face,
// edge or corner intersect, zero-extent boxes take part, and no candidate needs filtering:
// only the caller's exact test runs on the pairs found. tests/adapters_collide_test.cpp
// compares the answer with brute force (touching lattices, duplicates, points, 1e8 offsets).
//
// update(): the rtree's own incremental path. Each box whose coordinates changed is removed
// (by its old value: our copy) and inserted again by R* insertion (ChooseSubtree, forced
// reinsertion, split); boxes that did not move are not touched. The packed tree thus ages as
// an R*-tree built by insertion would; a rebuild would be the packing constructor again.
//
// memory_bytes(): every node the tree allocates passes through a counting allocator, plus our
// copy of the boxes (kept for update()'s removals and for the queries' boxes).

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <boost/iterator/function_output_iterator.hpp>

#include "harness/collide_adapters.hpp"
#include "counting_allocator.hpp"

namespace harness {
namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;

// The rtree's node allocations, counted (counting_allocator.hpp).
using boost_adapters::counting_allocator;

// The registry's configuration (peer_registry.hpp: params rstar<16>, build packed).
constexpr std::size_t node_capacity = 16;

using bg_point = bg::model::point<double, 3, bg::cs::cartesian>;
using bg_box = bg::model::box<bg_point>;
using value = std::pair<bg_box, std::uint32_t>;
using allocator = counting_allocator<value>;
using params = bgi::rstar<node_capacity>;
using tree_type = bgi::rtree<value, params, bgi::indexable<value>, bgi::equal_to<value>, allocator>;

bg_box to_bg(const collide_box& b) {
    return bg_box(bg_point(b.lo[0], b.lo[1], b.lo[2]), bg_point(b.hi[0], b.hi[1], b.hi[2]));
}

bool same_box(const collide_box& a, const collide_box& b) {
    return a.lo == b.lo && a.hi == b.hi;
}

class boost_rtree_collide_index final : public collide_index {
public:
    boost_rtree_collide_index() { reset({}); }
    boost_rtree_collide_index(const boost_rtree_collide_index&) = delete;
    boost_rtree_collide_index& operator=(const boost_rtree_collide_index&) = delete;

    std::string name() const override { return "boost_rtree_collide"; }

    void build(std::span<const collide_box> boxes) override {
        boxes_.assign(boxes.begin(), boxes.end());
        std::vector<value> values(boxes_.size());
        for (std::size_t i = 0; i < boxes_.size(); ++i) values[i] = {to_bg(boxes_[i]), static_cast<std::uint32_t>(i)};
        reset(values);
    }

    void update(std::span<const collide_box> boxes) override {
        if (boxes.size() != boxes_.size())
            throw std::invalid_argument("boost_rtree_collide: update() needs the built boxes' count");
        for (std::size_t i = 0; i < boxes.size(); ++i) {
            if (same_box(boxes[i], boxes_[i])) continue;
            const auto id = static_cast<std::uint32_t>(i);
            if (tree_->remove(value{to_bg(boxes_[i]), id}) != 1)
                throw std::logic_error("boost_rtree_collide: box " + std::to_string(i) + " was not in the tree");
            boxes_[i] = boxes[i];
            tree_->insert(value{to_bg(boxes_[i]), id});
        }
    }

    std::vector<index_pair> self_pairs(const exact_test& exact) override {
        std::vector<index_pair> out;
        if (boxes_.size() < 2) return out;
        for (std::size_t i = 0; i < boxes_.size(); ++i) {
            const auto a = static_cast<std::uint32_t>(i);
            tree_->query(bgi::intersects(to_bg(boxes_[i])), boost::make_function_output_iterator([&](const value& v) {
                             const std::uint32_t b = v.second;
                             if (b <= a) return;  // itself, or a pair reported from b's query
                             if (exact && !exact(a, b)) return;
                             out.emplace_back(a, b);
                         }));
        }
        sort_unique_pairs(out);
        return out;
    }

    std::vector<index_pair> pairs_with(std::span<const collide_box> others, const exact_test& exact) override {
        std::vector<index_pair> out;
        if (boxes_.empty() || others.empty()) return out;
        for (std::size_t j = 0; j < others.size(); ++j) {
            const auto b = static_cast<std::uint32_t>(j);
            tree_->query(bgi::intersects(to_bg(others[j])), boost::make_function_output_iterator([&](const value& v) {
                             const std::uint32_t a = v.second;
                             if (exact && !exact(a, b)) return;
                             out.emplace_back(a, b);
                         }));
        }
        sort_unique_pairs(out);
        return out;
    }

    std::size_t memory_bytes() const override {
        return sizeof(*this) + tree_bytes_ + boxes_.capacity() * sizeof(collide_box);
    }

private:
    // A fresh packed tree over `values` (the range constructor bulk-loads).
    void reset(const std::vector<value>& values) {
        tree_.reset();  // frees the old nodes, so the counter restarts from the new tree alone
        tree_bytes_ = 0;
        tree_ = std::make_unique<tree_type>(values.begin(), values.end(), params(), bgi::indexable<value>(),
                                            bgi::equal_to<value>(), allocator(&tree_bytes_));
    }

    std::size_t tree_bytes_ = 0;  // the counting allocator's counter: declared before tree_
    std::unique_ptr<tree_type> tree_;
    std::vector<collide_box> boxes_;  // our copy: the queries' boxes and update()'s old values
};

}  // namespace

std::unique_ptr<collide_index> make_boost_rtree_collide_index() {
    return std::make_unique<boost_rtree_collide_index>();
}

}  // namespace harness
