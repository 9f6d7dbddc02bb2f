// Collision peers (harness/collide_adapters.hpp: CGAL box_intersection_d, FCL's dynamic AABB
// tree / SaP / spatial hashing, Embree rtcCollide, Boost.Geometry's R*-tree) against a
// brute-force O(n^2) oracle on CLOSED boxes written here: every peer (make_peer_collide_indices,
// so a new one joins every test below without a line here) must return the identical pair
// set, self and bipartite, after update() with moved boxes, and with an exact test that
// rejects pairs of odd index sum. The boxes stress the three ways peers lose or invent
// pairs: ties (boxes on an integer grid touching on faces, edges and corners; identical
// boxes; zero-extent boxes),
// float rounding (Embree: coordinates offset by 1e8, extents of 1e-12) and size outliers (a
// huge box overlapping everything). Every seed is logged through SCOPED_TRACE.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/collide_adapters.hpp"
#include "harness/peer_registry.hpp"
#include "harness/tuning_sweep.hpp"

namespace {

using harness::collide_box;
using harness::collide_index;
using harness::index_pair;

// --- the oracle -------------------------------------------------------------------------

bool oracle_overlap(const collide_box& a, const collide_box& b) {
    for (std::size_t k = 0; k < 3; ++k)
        if (!(a.lo[k] <= b.hi[k] && b.lo[k] <= a.hi[k])) return false;
    return true;
}

bool odd_sum_rejected(std::uint32_t i, std::uint32_t j) {
    return (i + j) % 2 == 0;
}

std::vector<index_pair> oracle_self(std::span<const collide_box> boxes, bool filter_odd) {
    std::vector<index_pair> out;
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
        for (std::uint32_t j = i + 1; j < boxes.size(); ++j)
            if (oracle_overlap(boxes[i], boxes[j]) && (!filter_odd || odd_sum_rejected(i, j))) out.emplace_back(i, j);
    return out;  // generated in lexicographic order
}

std::vector<index_pair> oracle_bipartite(std::span<const collide_box> built, std::span<const collide_box> others,
                                         bool filter_odd) {
    std::vector<index_pair> out;
    for (std::uint32_t i = 0; i < built.size(); ++i)
        for (std::uint32_t j = 0; j < others.size(); ++j)
            if (oracle_overlap(built[i], others[j]) && (!filter_odd || odd_sum_rejected(i, j))) out.emplace_back(i, j);
    return out;
}

// --- workloads ----------------------------------------------------------------------------

collide_box make_box(double x, double y, double z, double ex, double ey, double ez) {
    return collide_box{{x, y, z}, {x + ex, y + ey, z + ez}};
}

// A mix on a [0, side)^3 region shifted by `offset`: grid boxes with integer corners and
// extents 0..2 per axis (touching faces, edges and corners; flat and point boxes), continuous
// boxes, zero-extent points, exact duplicates of earlier boxes, boxes of extent 1e-12, and
// (with `huge`) one box overlapping all the others.
std::vector<collide_box> random_boxes(std::mt19937_64& rng, std::size_t n, double side, double offset, bool huge) {
    std::uniform_real_distribution<double> u(0.0, side), extent(0.0, 2.0);
    std::uniform_int_distribution<int> cell(0, static_cast<int>(side) - 1), grid_extent(0, 2), kind(0, 9);
    std::vector<collide_box> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const int k = kind(rng);
        if (huge && i == n / 2) {
            out.push_back(make_box(offset - side, offset - side, offset - side, 3 * side, 3 * side, 3 * side));
        } else if (k < 4) {
            out.push_back(make_box(offset + cell(rng), offset + cell(rng), offset + cell(rng), grid_extent(rng),
                                   grid_extent(rng), grid_extent(rng)));
        } else if (k < 6) {
            out.push_back(
                make_box(offset + u(rng), offset + u(rng), offset + u(rng), extent(rng), extent(rng), extent(rng)));
        } else if (k < 7) {
            out.push_back(make_box(offset + cell(rng), offset + cell(rng), offset + u(rng), 0, 0, 0));
        } else if (k < 8 && !out.empty()) {
            out.push_back(out[std::uniform_int_distribution<std::size_t>(0, out.size() - 1)(rng)]);
        } else if (k < 9) {
            out.push_back(make_box(offset + u(rng), offset + cell(rng), offset + u(rng), 1e-12, 1e-12, 0));
        } else {
            out.push_back(make_box(offset + cell(rng), offset + u(rng), offset + cell(rng), 1, extent(rng), 1));
        }
    }
    return out;
}

// The same boxes moved: integer shifts (grid boxes stay on the grid, so new touching pairs
// appear), continuous shifts, resizes (if `resize`; FCL's SaP follows translations
// incrementally and rebuilds otherwise, so both paths are taken), and some boxes left in place.
std::vector<collide_box> moved(std::mt19937_64& rng, std::vector<collide_box> boxes, bool resize) {
    std::uniform_int_distribution<int> step(-1, 1), kind(0, resize ? 3 : 2);
    std::uniform_real_distribution<double> small(-0.5, 0.5);
    for (collide_box& b : boxes) {
        const int k = kind(rng);
        for (std::size_t a = 0; a < 3; ++a) {
            if (k == 0) {
                const double d = step(rng);
                b.lo[a] += d;
                b.hi[a] += d;
            } else if (k == 1) {
                const double d = small(rng);
                b.lo[a] += d;
                b.hi[a] += d;
            } else if (k == 3) {
                b.hi[a] = b.lo[a] + (b.hi[a] - b.lo[a]) * 0.5;
            }
        }
    }
    return boxes;
}

// The exact test the peers receive: rejects odd index sums, and checks that it is only called
// on pairs whose boxes overlap (the peers filter their candidates before the narrow phase)
// and, for self pairs, with i < j.
collide_index::exact_test checked_exact(std::span<const collide_box> built, std::span<const collide_box> others,
                                        bool self) {
    return [built, others, self](std::uint32_t i, std::uint32_t j) {
        EXPECT_LT(i, built.size());
        EXPECT_LT(j, others.size());
        if (i < built.size() && j < others.size()) {
            EXPECT_TRUE(oracle_overlap(built[i], others[j])) << i << "," << j;
        }
        if (self) {
            EXPECT_LT(i, j);
        }
        return odd_sum_rejected(i, j);
    };
}

std::string describe_first_difference(const std::vector<index_pair>& got, const std::vector<index_pair>& want) {
    std::vector<index_pair> missing, extra;
    std::set_difference(want.begin(), want.end(), got.begin(), got.end(), std::back_inserter(missing));
    std::set_difference(got.begin(), got.end(), want.begin(), want.end(), std::back_inserter(extra));
    std::string s = "got " + std::to_string(got.size()) + " pairs, want " + std::to_string(want.size()) + "; " +
                    std::to_string(missing.size()) + " missing, " + std::to_string(extra.size()) + " extra";
    if (!missing.empty())
        s += "; first missing (" + std::to_string(missing[0].first) + "," + std::to_string(missing[0].second) + ")";
    if (!extra.empty())
        s += "; first extra (" + std::to_string(extra[0].first) + "," + std::to_string(extra[0].second) + ")";
    return s;
}

#define EXPECT_SAME_PAIRS(got, want) EXPECT_TRUE((got) == (want)) << describe_first_difference((got), (want))

// All four answers (self, bipartite; boxes only and with the exact test) against the oracle.
void check_all_queries(collide_index& index, std::span<const collide_box> boxes, std::span<const collide_box> others) {
    {
        SCOPED_TRACE("self_pairs");
        EXPECT_SAME_PAIRS(index.self_pairs(), oracle_self(boxes, false));
    }
    {
        SCOPED_TRACE("self_pairs with exact test");
        EXPECT_SAME_PAIRS(index.self_pairs(checked_exact(boxes, boxes, true)), oracle_self(boxes, true));
    }
    {
        SCOPED_TRACE("pairs_with");
        EXPECT_SAME_PAIRS(index.pairs_with(others), oracle_bipartite(boxes, others, false));
    }
    {
        SCOPED_TRACE("pairs_with with exact test");
        EXPECT_SAME_PAIRS(index.pairs_with(others, checked_exact(boxes, others, false)),
                          oracle_bipartite(boxes, others, true));
    }
}

// Every collision adapter has its registry line, once; with every peer's CMake option on (the
// default build) every collision peer the registry lists has its adapter. A new peer needs no
// line here.
TEST(adapters_collide, every_configured_peer_is_registered_once) {
    const auto peers = harness::make_peer_collide_indices();
    std::set<std::string> names, registered;
    for (const auto& p : harness::registered_peers())
        if (p.takes_part_in(harness::in::collide_static)) registered.insert(p.name);
    for (const auto& p : peers) {
        EXPECT_TRUE(registered.count(p->name())) << p->name() << " has no collide line in peer_registry.hpp";
        names.insert(p->name());
    }
    EXPECT_EQ(names.size(), peers.size());
#if SPATIAL_EVERY_PEER_ADAPTER_BUILT
    EXPECT_EQ(names, registered);
#endif
    if (peers.empty()) GTEST_SKIP() << "no collision peer configured";
}

// The sweep makes each peer once per configuration (its registry one first, unlabelled); each
// swept one is labelled with what it changes, in the registry's terms. The tests below run
// every configuration (make_peer_collide_indices(true)): the suite times a swept
// configuration only after validating it, and it is tested here like the default.
TEST(adapters_collide, the_sweep_makes_every_configuration_once) {
    const auto defaults = harness::make_peer_collide_indices(false);
    const auto all = harness::make_peer_collide_indices(true);
    std::size_t expected = 0;
    for (const auto& p : defaults) {
        EXPECT_EQ(p->configuration(), "") << p->name();
        expected += 1 + harness::tuning_sweep(p->name()).size();
    }
    EXPECT_EQ(all.size(), expected);
    std::set<std::string> labels;
    for (const auto& p : all)
        EXPECT_TRUE(labels.insert(harness::labelled(*p)).second) << harness::labelled(*p) << " twice";
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    for (const char* label :
         {"cgal_box_intersection", "cgal_box_intersection[cutoff=100]", "cgal_box_intersection[cutoff=100000]"})
        EXPECT_TRUE(labels.count(label)) << label;
#endif
#if defined(SPATIAL_HAVE_EMBREE) && SPATIAL_HAVE_EMBREE
    for (const char* label :
         {"embree_collide", "embree_collide[build_quality=low]", "embree_collide[build_quality=high]"})
        EXPECT_TRUE(labels.count(label)) << label;
#endif
#if defined(SPATIAL_HAVE_BOOST_GEOMETRY) && SPATIAL_HAVE_BOOST_GEOMETRY
    // Boost's node capacity is a template argument: one configuration, nothing swept.
    EXPECT_TRUE(labels.count("boost_rtree_collide"));
    EXPECT_TRUE(harness::tuning_sweep("boost_rtree_collide").empty());
#endif
}

// A setting a peer cannot run is an error naming the peer and the setting, not a silent default.
TEST(adapters_collide, bad_settings_are_errors_that_name_them) {
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    for (const char* bad : {"0", "-10", "ten", "10x", ""}) {
        try {
            (void)harness::make_cgal_box_intersection_collide_index({{"cutoff", bad}});
            ADD_FAILURE() << "cutoff=" << bad << " was accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("cgal_box_intersection: setting cutoff="), std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW((void)harness::make_cgal_box_intersection_collide_index({}), std::invalid_argument);
#endif
#if defined(SPATIAL_HAVE_EMBREE) && SPATIAL_HAVE_EMBREE
    for (const char* bad : {"refit", "LOW", ""}) {
        try {
            (void)harness::make_embree_collide_index({{"build_quality", bad}});
            ADD_FAILURE() << "build_quality=" << bad << " was accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("embree_collide: setting build_quality="), std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW((void)harness::make_embree_collide_index({}), std::invalid_argument);
#endif
}

// Enough boxes that CGAL's segment tree splits at every swept cutoff but the largest (which
// scans): each configuration's self and bipartite pairs against brute force.
TEST(adapters_collide, every_configuration_on_thousands_of_boxes) {
    std::mt19937_64 rng(20261126);
    const std::vector<collide_box> boxes = random_boxes(rng, 6000, 40, 0, false);
    const std::vector<collide_box> others = random_boxes(rng, 2500, 40, 0, false);
    const auto want_self = oracle_self(boxes, false);
    const auto want_bipartite = oracle_bipartite(boxes, others, false);
    ASSERT_GT(want_self.size(), 1000u);
    for (auto& peer : harness::make_peer_collide_indices(true)) {
        SCOPED_TRACE(harness::labelled(*peer));
        peer->build(boxes);
        EXPECT_SAME_PAIRS(peer->self_pairs(), want_self);
        EXPECT_SAME_PAIRS(peer->pairs_with(others), want_bipartite);
    }
}

TEST(adapters_collide, random_boxes_self_bipartite_and_after_updates_match_brute_force) {
    struct workload {
        std::size_t n, others;
        double side, offset;
        bool huge;
    };
    const std::vector<workload> workloads = {
        {2, 3, 4, 0, false},       {40, 25, 6, 0, false},     {300, 120, 10, 0, false}, {300, 200, 10, 0, true},
        {250, 100, 8, -3.5, true}, {200, 150, 8, 1e8, false}, {150, 80, 5, -1e8, true},
    };
    for (auto& peer : harness::make_peer_collide_indices(true)) {
        SCOPED_TRACE(harness::labelled(*peer));
        for (const std::uint64_t seed : {1u, 2u, 3u, 4u, 5u}) {
            for (const workload& w : workloads) {
                SCOPED_TRACE("seed " + std::to_string(seed) + ", n " + std::to_string(w.n) + ", others " +
                             std::to_string(w.others) + ", side " + std::to_string(w.side) + ", offset " +
                             std::to_string(w.offset) + (w.huge ? ", huge box" : ""));
                std::mt19937_64 rng(seed * 7919 + w.n);
                std::vector<collide_box> boxes = random_boxes(rng, w.n, w.side, w.offset, w.huge);
                const std::vector<collide_box> others = random_boxes(rng, w.others, w.side, w.offset, false);
                peer->build(boxes);
                EXPECT_GT(peer->memory_bytes(), 0u);
                check_all_queries(*peer, boxes, others);
                for (int step = 1; step <= 3; ++step) {
                    SCOPED_TRACE("after update " + std::to_string(step));
                    boxes = moved(rng, std::move(boxes), step == 3);
                    peer->update(boxes);
                    check_all_queries(*peer, boxes, others);
                }
            }
        }
    }
}

// A 5 x 5 x 5 lattice of unit cubes: each touches its (up to) 26 neighbours only on faces,
// edges and corners; all of those pairs are overlaps of closed boxes. Also at an offset of
// 1e8, where the corners are exact doubles but not exact floats.
TEST(adapters_collide, touching_lattice_reports_every_face_edge_and_corner_contact) {
    for (const double offset : {0.0, 1e8, -12.25}) {
        SCOPED_TRACE("offset " + std::to_string(offset));
        std::vector<collide_box> lattice;
        for (int x = 0; x < 5; ++x)
            for (int y = 0; y < 5; ++y)
                for (int z = 0; z < 5; ++z) lattice.push_back(make_box(offset + x, offset + y, offset + z, 1, 1, 1));
        // Each axis contributes pairs of offsets (dx, dy, dz) in {-1,0,1}^3 \ 0, halved:
        // ((3*5-2)^3 - 5^3) / 2 = (13^3 - 125) / 2 = 1036.
        const std::vector<index_pair> want = oracle_self(lattice, false);
        ASSERT_EQ(want.size(), 1036u);
        // The lattice shifted by half a cell overlaps it properly; shifted by a whole cell it
        // only touches.
        std::vector<collide_box> shifted = lattice;
        for (collide_box& b : shifted)
            for (std::size_t k = 0; k < 3; ++k) {
                b.lo[k] += 5;
                b.hi[k] += 5;
            }
        for (auto& peer : harness::make_peer_collide_indices(true)) {
            SCOPED_TRACE(harness::labelled(*peer));
            peer->build(lattice);
            EXPECT_SAME_PAIRS(peer->self_pairs(), want);
            const std::vector<index_pair> corner = peer->pairs_with(shifted);
            EXPECT_SAME_PAIRS(corner, oracle_bipartite(lattice, shifted, false));
            EXPECT_EQ(corner.size(), 1u);  // only the corner (offset+5)^3 is shared
            peer->update(shifted);         // moved by whole cells: the same contacts again
            EXPECT_SAME_PAIRS(peer->self_pairs(), want);
        }
    }
}

// update() carrying every box far from where it was built: the peers' margins and limits were
// sized for the built coordinates (FCL SaP's relative margin, the spatial hash's scene limits)
// and must be renewed, not reused.
TEST(adapters_collide, update_far_from_the_built_scene) {
    for (const std::uint64_t seed : {11u, 12u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        std::mt19937_64 rng(seed);
        std::vector<collide_box> boxes = random_boxes(rng, 200, 6, 0, seed % 2 == 0);
        const std::vector<collide_box> others = random_boxes(rng, 60, 6, 1e6, false);
        for (auto& peer : harness::make_peer_collide_indices(true)) {
            SCOPED_TRACE(harness::labelled(*peer));
            std::vector<collide_box> moving = boxes;
            peer->build(moving);
            check_all_queries(*peer, moving, others);
            for (collide_box& b : moving)
                for (std::size_t k = 0; k < 3; ++k) {
                    b.lo[k] += 1e6;
                    b.hi[k] += 1e6;
                }
            peer->update(moving);
            check_all_queries(*peer, moving, others);
        }
    }
}

TEST(adapters_collide, identical_and_zero_extent_boxes) {
    std::vector<collide_box> same(20, make_box(0.5, 0.5, 0.5, 0, 0, 0));  // one point, 20 times
    std::vector<collide_box> cubes(15, make_box(-1, -1, -1, 2, 2, 2));
    const std::vector<collide_box> probe = {make_box(0.5, 0.5, 0.5, 0, 0, 0), make_box(0.5, 0.5, 0.6, 0, 0, 0),
                                            make_box(1, 1, 1, 0, 0, 0)};
    for (auto& peer : harness::make_peer_collide_indices(true)) {
        SCOPED_TRACE(harness::labelled(*peer));
        peer->build(same);
        EXPECT_EQ(peer->self_pairs().size(), 20u * 19u / 2u);
        EXPECT_SAME_PAIRS(peer->pairs_with(probe), oracle_bipartite(same, probe, false));
        peer->build(cubes);
        EXPECT_SAME_PAIRS(peer->self_pairs(), oracle_self(cubes, false));
        EXPECT_SAME_PAIRS(peer->pairs_with(probe), oracle_bipartite(cubes, probe, false));
        EXPECT_EQ(peer->pairs_with(probe).size(), 15u * 3u);  // (1,1,1) is on the cubes' corner
    }
}

TEST(adapters_collide, empty_and_single_box) {
    const std::vector<collide_box> none;
    const std::vector<collide_box> one = {make_box(0, 0, 0, 1, 1, 1)};
    const std::vector<collide_box> others = {make_box(1, 1, 1, 1, 1, 1), make_box(2, 2, 2, 1, 1, 1)};
    for (auto& peer : harness::make_peer_collide_indices(true)) {
        SCOPED_TRACE(harness::labelled(*peer));
        peer->build(none);
        EXPECT_TRUE(peer->self_pairs().empty());
        EXPECT_TRUE(peer->pairs_with(others).empty());
        EXPECT_TRUE(peer->pairs_with(none).empty());
        peer->update(none);
        EXPECT_TRUE(peer->self_pairs().empty());

        peer->build(one);
        EXPECT_TRUE(peer->self_pairs().empty());
        EXPECT_TRUE(peer->pairs_with(none).empty());
        EXPECT_EQ(peer->pairs_with(others), (std::vector<index_pair>{{0, 0}}));  // corner contact
        const std::vector<collide_box> moved_one = {make_box(2.5, 2.5, 2.5, 1, 1, 1)};
        peer->update(moved_one);
        EXPECT_TRUE(peer->self_pairs().empty());
        EXPECT_EQ(peer->pairs_with(others), (std::vector<index_pair>{{0, 1}}));
    }
}

}  // namespace
