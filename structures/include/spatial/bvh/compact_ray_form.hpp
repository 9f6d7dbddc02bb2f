#pragma once
// spatial::bvh_detail::compact_ray_form<O> — what the wide ray layout (wide_ray_layout.hpp)
// keeps in its leaves to test thin rays, when it can do better than a copy of each object:
// blocks of `lanes` objects, stored lane-wise and tested together with SIMD.
//
// Why: incoherent rays over ~1e6 triangles are bound by cache misses, and a leaf's objects
// are the last miss of every descent; the leaf test then runs one object at a time. A 3D
// double triangle is 120 bytes (three vertices and its bounding box) while the watertight ray
// test needs only the 72 bytes of vertices, and the test of 4 triangles costs about as much
// in 4-lane SIMD as the test of one. The layout therefore stores each leaf's triangles as
// blocks of 4 (vertex[k][axis][lane], the last block padded with copies of its first
// triangle), with their ids in the same block (the hit's id costs no further cache miss),
// and tests thin rays on the blocks alone, with the triangle's own lane-wise test
// (objects::triangle::intersect_thin_lanes: the same floating-point operations per lane, the
// same hit record, the same winner on ties as testing the triangles in order). Thick rays
// need the objects themselves and read them from the container.
//
// enabled = false (every other object): the layout copies the objects and tests them one by
// one. Cost: O(1) per object to fill; memory: sizeof(block) per `lanes` objects of a leaf.

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "spatial/objects/triangle.hpp"

namespace spatial::bvh_detail {

template <class O>
struct compact_ray_form {
    static constexpr bool enabled = false;
    static constexpr std::size_t lanes = 1;
    struct block {};  // never stored
};

// float and double: the scalars GCC/Clang vector extensions take (others copy the objects).
template <class T>
    requires(std::is_same_v<T, float> || std::is_same_v<T, double>)
struct compact_ray_form<objects::triangle<T, 3>> {
    static constexpr bool enabled = true;
    static constexpr std::size_t lanes = 4;
    using object = objects::triangle<T, 3>;
    typedef T lane_values __attribute__((vector_size(lanes * sizeof(T))));
    // 5 cache lines for double (288 bytes of vertices and the ids), 3 for float.
    struct alignas(64) block {
        lane_values vertex[3][3];  // [vertex][axis], one triangle per lane
        std::uint32_t id[lanes];   // the layout's id of each lane's object (its slot)
    };

    static void set(block& b, std::size_t lane, const object& t, std::uint32_t id) {
        for (std::size_t k = 0; k < 3; ++k)
            for (std::size_t a = 0; a < 3; ++a) b.vertex[k][a][lane] = t.vertex(k)[a];
        b.id[lane] = id;
    }
    // The triangles in lanes [0, count) tested in lane order as object::intersect(ray, 0,
    // info) would: the lane hit (info lowered), or -1.
    template <class Info>
    static int intersect(const block& b, std::size_t count, const typename object::prepared_ray& ray, Info& info) {
        return object::intersect_thin_lanes(b.vertex, count, ray, info);
    }
};

}  // namespace spatial::bvh_detail
