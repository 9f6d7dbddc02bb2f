#pragma once
// harness::object_ray_index<O> — first-hit ray casting over stored objects other than
// triangles (objects::box<double, 3>, and point<double, 3> hit by a thick ray): the interface
// the raycast suite's object workloads (`boxes`, `points`) time, with our containers and
// Embree's user geometry behind it.
//
// A scene is built for one ray thickness (Embree must know its primitives' bounds, grown by
// the ray's radius, before any ray is cast); every ray cast on it uses that thickness.
// Hits are compared by distance along the ray (directions are normalised by the suite).

#include <cstddef>
#include <memory>
#include <span>
#include <string>

#include "harness/ray_index.hpp"
#include "spatial/core/capabilities.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"

namespace harness {

template <class O>
class object_ray_index {
public:
    using scalar_type = typename O::scalar_type;
    using point_type = spatial::point_type_of<O>;
    virtual ~object_ray_index() = default;

    virtual std::string name() const = 0;
    virtual std::string bv() const { return {}; }
    // Replace the contents. The caller keeps `objects` alive and unchanged until the next
    // build (a peer may reference them from its callbacks).
    virtual void build(std::span<const O> objects, scalar_type thickness) = 0;
    virtual std::size_t memory_bytes() const = 0;
    // First hit with 0 <= t < t_max of the ray (origin, direction) of the build's thickness.
    virtual bool intersect(const point_type& origin, const point_type& direction, scalar_type t_max,
                           ray_hit<scalar_type>& hit) = 0;
};

// Any of our containers of O behind the interface (bulk insert + prepare_rays when offered).
template <class Container>
class container_object_ray_index final : public object_ray_index<typename Container::value_type> {
public:
    using O = typename Container::value_type;
    using T = typename O::scalar_type;
    using typename object_ray_index<O>::point_type;

    explicit container_object_ray_index(std::string name, std::string bv = {})
        : name_(std::move(name)), bv_(std::move(bv)) {}
    std::string name() const override { return name_; }
    std::string bv() const override { return bv_; }
    void build(std::span<const O> objects, T thickness) override {
        c_.clear();
        c_.insert(objects.begin(), objects.end());
        if constexpr (spatial::ray_preparation<Container>) c_.prepare_rays();
        thickness_ = thickness;
    }
    std::size_t memory_bytes() const override { return c_.memory_bytes(); }
    bool intersect(const point_type& origin, const point_type& direction, T t_max, ray_hit<T>& hit) override {
        spatial::intersect_info<point_type> info;
        info.hit_time = t_max;
        if (c_.intersect_object(origin, direction, thickness_, info) == c_.end()) return false;
        hit.t = info.hit_time;
        return true;
    }

private:
    std::string name_, bv_;
    Container c_;
    T thickness_ = 0;
};

// Embree 3 user geometry (RTC_GEOMETRY_TYPE_USER) over boxes or points, defined in the
// Embree adapter when SPATIAL_HAVE_EMBREE. Embree builds and traverses its BVH in float over
// primitive bounds we supply — each object's box grown by the ray thickness plus a margin
// that covers float rounding of the ray (2^-16 of the scene's and the origins' magnitude) —
// and calls back our exact double test (O::intersect with the caller's double ray, passed
// through an extended RTCIntersectContext), which shortens the ray to the exact hit. So its
// answers are the exact ones; the suite checks them against brute force like ours.
// name() "embree_user".
std::unique_ptr<object_ray_index<spatial::objects::box<double, 3>>> make_embree_box_ray_index();
std::unique_ptr<object_ray_index<spatial::point<double, 3>>> make_embree_point_ray_index();

}  // namespace harness
