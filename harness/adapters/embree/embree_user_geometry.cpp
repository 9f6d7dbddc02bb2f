// Embree 3 user geometry (RTC_GEOMETRY_TYPE_USER) over boxes and points behind
// harness::object_ray_index (see harness/object_ray_index.hpp for the contract).
//
// Embree knows user primitives only through two callbacks: their bounds (float boxes; Embree
// builds its BVH over them with its SAH builder) and an intersect function it calls for every
// primitive whose bounds the float ray enters. The intersect callback runs OUR exact double
// test (O::intersect) on the caller's double ray, which travels with the query in an
// RTCIntersectContext extended by the ray (the pattern of Embree's own tutorials), and
// shortens Embree's float ray to the exact hit. Exactness needs the float traversal never
// to cull a primitive the double test would hit, so the bounds are the object's box grown by
// the ray thickness and a margin of 2^-16 (|scene|_inf + |origin|_inf) — far above the float
// rounding of origin and direction (about 2^-23 of those magnitudes) — and rays whose origin
// is more than 64 scene magnitudes away are refused (the margin was sized for the scene).

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/object_ray_index.hpp"
#include "spatial/bv/rounding.hpp"
#include "spatial/core/object_geometry.hpp"
#include "embree_device.hpp"

namespace harness {
namespace {

template <class O>
class embree_object_index final : public object_ray_index<O> {
public:
    using T = double;
    using P = spatial::point<double, 3>;

    embree_object_index() = default;
    ~embree_object_index() override {
        release_scene();
    }
    embree_object_index(const embree_object_index&) = delete;
    embree_object_index& operator=(const embree_object_index&) = delete;

    std::string name() const override { return "embree_user"; }

    void build(std::span<const O> objects, T thickness) override {
        release_scene();
        objects_ = objects;
        thickness_ = thickness;
        magnitude_ = 0;
        for (const O& x : objects)
            for (std::size_t k = 0; k < 3; ++k)
                magnitude_ = std::max({magnitude_, std::abs(spatial::object_lower(x, k)),
                                       std::abs(spatial::object_upper(x, k))});
        grow_ = thickness + 0x1p-16 * 65 * magnitude_ + std::numeric_limits<float>::min();
        scene_ = rtcNewScene(device_.get());
        if (!scene_) device_.fail("rtcNewScene");
        if (!objects.empty()) {
            RTCGeometry g = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_USER);
            if (!g) device_.fail("rtcNewGeometry(USER)");
            rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(objects.size()));
            rtcSetGeometryUserData(g, this);
            rtcSetGeometryBoundsFunction(g, &bounds_of, this);
            rtcSetGeometryIntersectFunction(g, &intersect_one);
            rtcSetGeometryOccludedFunction(g, &occluded_one);
            rtcCommitGeometry(g);
            rtcAttachGeometry(scene_, g);
            rtcReleaseGeometry(g);
        }
        rtcCommitScene(scene_);
        device_.check("rtcCommitScene");
    }
    std::size_t memory_bytes() const override {
        const long long embree = device_.bytes();
        return sizeof(*this) + static_cast<std::size_t>(embree > 0 ? embree : 0) + objects_.size_bytes();
    }

    bool intersect(const P& origin, const P& direction, T t_max, ray_hit<T>& hit) override {
        if (objects_.empty()) return false;
        for (std::size_t k = 0; k < 3; ++k)
            if (!(std::abs(origin[k]) <= 64 * magnitude_))
                throw std::invalid_argument("embree_user: ray origin beyond 64 scene magnitudes (the bounds' float "
                                            "margin was sized for the scene)");
        query q;
        rtcInitIntersectContext(&q.context);
        q.origin = &origin;
        q.direction = &direction;
        q.best_t = t_max;
        RTCRayHit rh;
        rh.ray.org_x = static_cast<float>(origin[0]);
        rh.ray.org_y = static_cast<float>(origin[1]);
        rh.ray.org_z = static_cast<float>(origin[2]);
        rh.ray.dir_x = static_cast<float>(direction[0]);
        rh.ray.dir_y = static_cast<float>(direction[1]);
        rh.ray.dir_z = static_cast<float>(direction[2]);
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = spatial::detail_rounding::round_up<float>(t_max);  // never below the exact limit: the callback decides
        rh.ray.time = 0.0f;
        rh.ray.mask = ~0u;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &q.context, &rh);
        if (q.best == no_hit) return false;
        hit.t = q.best_t;
        hit.triangle = q.best;  // the object's index
        return true;
    }

private:
    static constexpr unsigned no_hit = std::numeric_limits<unsigned>::max();
    // The extended context: Embree passes &context back to the callbacks.
    struct query {
        RTCIntersectContext context;
        const P* origin = nullptr;
        const P* direction = nullptr;
        T best_t = 0;
        unsigned best = no_hit;
    };

    static void bounds_of(const RTCBoundsFunctionArguments* args) {
        const auto* self = static_cast<const embree_object_index*>(args->geometryUserPtr);
        const O& x = self->objects_[args->primID];
        RTCBounds* b = args->bounds_o;
        b->lower_x = spatial::detail_rounding::round_down<float>(spatial::object_lower(x, 0) - self->grow_);
        b->lower_y = spatial::detail_rounding::round_down<float>(spatial::object_lower(x, 1) - self->grow_);
        b->lower_z = spatial::detail_rounding::round_down<float>(spatial::object_lower(x, 2) - self->grow_);
        b->upper_x = spatial::detail_rounding::round_up<float>(spatial::object_upper(x, 0) + self->grow_);
        b->upper_y = spatial::detail_rounding::round_up<float>(spatial::object_upper(x, 1) + self->grow_);
        b->upper_z = spatial::detail_rounding::round_up<float>(spatial::object_upper(x, 2) + self->grow_);
    }
    static void intersect_one(const RTCIntersectFunctionNArguments* args) {
        const auto* self = static_cast<const embree_object_index*>(args->geometryUserPtr);
        auto* q = reinterpret_cast<query*>(args->context);
        for (unsigned i = 0; i < args->N; ++i) {
            if (!args->valid[i]) continue;
            spatial::intersect_info<P> info;
            info.hit_time = q->best_t;
            if (!self->objects_[args->primID].intersect(*q->origin, *q->direction, self->thickness_, info)) continue;
            q->best_t = info.hit_time;
            q->best = args->primID;
            RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
            RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
            // Shorten the float ray to the exact hit (rounded up: nothing nearer is culled).
            RTCRayN_tfar(ray, args->N, i) = std::min(RTCRayN_tfar(ray, args->N, i), spatial::detail_rounding::round_up<float>(info.hit_time));
            RTCHitN_geomID(hit, args->N, i) = args->geomID;
            RTCHitN_primID(hit, args->N, i) = args->primID;
            RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
            RTCHitN_u(hit, args->N, i) = 0.0f;
            RTCHitN_v(hit, args->N, i) = 0.0f;
            RTCHitN_Ng_x(hit, args->N, i) = 0.0f;
            RTCHitN_Ng_y(hit, args->N, i) = 0.0f;
            RTCHitN_Ng_z(hit, args->N, i) = 1.0f;
        }
    }
    // Not used by the suite (first hits only); present because Embree requires both.
    static void occluded_one(const RTCOccludedFunctionNArguments* args) {
        const auto* self = static_cast<const embree_object_index*>(args->geometryUserPtr);
        auto* q = reinterpret_cast<query*>(args->context);
        for (unsigned i = 0; i < args->N; ++i) {
            if (!args->valid[i]) continue;
            spatial::intersect_info<P> info;
            info.hit_time = q->best_t;
            if (self->objects_[args->primID].intersect(*q->origin, *q->direction, self->thickness_, info))
                RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
        }
    }
    void release_scene() {
        if (scene_) rtcReleaseScene(scene_);
        scene_ = nullptr;
    }

    embree_device device_{"embree_user"};
    RTCScene scene_ = nullptr;
    std::span<const O> objects_;
    T thickness_ = 0, magnitude_ = 0, grow_ = 0;
};

}  // namespace

std::unique_ptr<object_ray_index<spatial::objects::box<double, 3>>> make_embree_box_ray_index() {
    return std::make_unique<embree_object_index<spatial::objects::box<double, 3>>>();
}
std::unique_ptr<object_ray_index<spatial::point<double, 3>>> make_embree_point_ray_index() {
    return std::make_unique<embree_object_index<spatial::point<double, 3>>>();
}

}  // namespace harness
