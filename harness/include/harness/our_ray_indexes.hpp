#pragma once
// Any of our containers of triangles behind harness::ray_index<T> — one template for all of
// them (brute_force, bvh<triangle, BV>, octree, uniform_grid, ...): a structure joins the
// raycast suite with one line in raycast_suite.cpp (our_structures()).
//
// build() is a bulk insert of the triangle objects (the container's best build) plus its
// ray preparation (prepare_rays(), when it has one);
// intersect() is intersect_object with thickness 0 and info.hit_time = t_max, the container
// contract's ray cast; occluded() the same cast (the contract has no any-hit query).
// Nodes visited: taken from the container when it reports them
// (spatial::reports_query_stats, as bvh does), else -1.

#include <string>
#include <utility>

#include "harness/ray_index.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/container_concept.hpp"
#include "spatial/core/intersect_info.hpp"

namespace harness {

template <class Container>
class container_ray_index final : public ray_index<typename Container::scalar_type> {
public:
    using T = typename Container::scalar_type;
    using typename ray_index<T>::point_type;
    using typename ray_index<T>::triangle_type;
    static_assert(spatial::spatial_container<Container>, "container_ray_index: not a spatial_container");
    static_assert(std::is_same_v<typename Container::value_type, triangle_type>,
                  "container_ray_index: the container must store spatial::objects::triangle<T, 3>");

    explicit container_ray_index(std::string name, std::string bv = {}) : name_(std::move(name)), bv_(std::move(bv)) {}
    std::string name() const override { return name_; }
    std::string bv() const override { return bv_; }

    // A bulk insert, plus the container's ray preparation when it has one (bvh's wide ray
    // layout, otherwise built by the first ray): build time includes everything a ray needs.
    void build(const datasets::triangle_mesh&, std::span<const triangle_type> triangles) override {
        c_.clear();
        c_.insert(triangles.begin(), triangles.end());
        if constexpr (spatial::ray_preparation<Container>) c_.prepare_rays();
    }
    std::size_t size() const override { return c_.size(); }
    std::size_t memory_bytes() const override { return c_.memory_bytes(); }

    bool intersect(const point_type& origin, const point_type& direction, T t_max, ray_hit<T>& hit) override {
        spatial::intersect_info<point_type> info;
        info.hit_time = t_max;
        const auto it = c_.intersect_object(origin, direction, T(0), info);
        if (it == c_.end()) return false;
        hit.t = info.hit_time;
        hit.triangle = ~std::uint32_t{0};  // containers identify objects by iterator, not mesh index
        return true;
    }
    bool occluded(const point_type& origin, const point_type& direction, T t_max) override {
        spatial::intersect_info<point_type> info;
        info.hit_time = t_max;
        return c_.intersect(origin, direction, T(0), info);
    }
    long long last_nodes_visited() const override {
        if constexpr (spatial::reports_query_stats<Container>)
            return static_cast<long long>(c_.last_query_stats().nodes_visited);
        else
            return -1;
    }

    std::vector<std::pair<std::string, double>> build_metrics() const override {
        if constexpr (spatial::reports_node_areas<Container>) {
            const auto [volumes, boxes] = c_.node_surface_areas();
            if (boxes > 0) return {{"node_area_ratio", volumes / boxes}};
        }
        return {};
    }

    Container& container() { return c_; }

private:
    std::string name_, bv_;
    Container c_;
};

}  // namespace harness
