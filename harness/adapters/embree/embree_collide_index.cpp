// Embree 3 rtcCollide behind harness::collide_index (declared in harness/collide_adapters.hpp).
//
// rtcCollide (Embree >= 3.8; Debian ships 3.13) traverses two BVHs together and calls back
// with candidate primitive pairs. It supports scenes made only of RTC_GEOMETRY_TYPE_USER
// geometry, so the boxes are one user geometry whose bounds callback returns each double box
// rounded OUTWARD to float (spatial/bv/rounding.hpp: the largest float <= lo, the smallest
// float >= hi). A float box therefore contains its double box, and two overlapping double
// boxes (closed: touching counts) have overlapping float boxes; Embree's node test is closed
// too (lower <= upper), so no overlapping pair can be culled. The float boxes do overlap more
// pairs than the doubles (touching after rounding), and Embree 3.13's user-geometry collider
// reports every primitive pair of two overlapping LEAVES, without a per-primitive test; the
// callback filters all of them with the exact closed double test (and then the caller's exact
// test), so the answer is exactly the closed-box one.
//
// Self collision is rtcCollide(scene, scene): Embree skips (i, i) but reports every other
// candidate in both orders, (i, j) from leaf pair (A, B) and (j, i) from (B, A) (the traversal
// of a tree with itself is symmetric: a leaf pair is reached iff its bounds overlap). The
// callback keeps i < j, so each pair is tested and reported once; sort_unique_pairs still
// removes any repeat.
//
// The callback can run on several of Embree's threads at once (rtcCollide splits the top of
// the traversal into jobs run by parallel_for); the device is created with threads=1 like the
// other Embree adapters, and the callback takes a mutex anyway (uncontended: tens of ns per
// call; 3.13 calls back once per candidate pair).
//
// update(): rtcCommitGeometry (Embree re-reads the bounds of a committed user geometry; there
// is no buffer to rtcUpdateGeometryBuffer) and rtcCommitScene, which rebuilds the BVH, or
// refits it under build_quality=low (below).
//
// Coordinates must lie within float range (|x| < 3.4e38): beyond it the rounded bounds would
// be infinite.

#include <embree3/rtcore.h>

#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harness/collide_adapters.hpp"
#include "harness/tuning_sweep.hpp"
#include "spatial/bv/rounding.hpp"
#include "embree_build_quality.hpp"
#include "embree_device.hpp"

namespace harness {
namespace {

// The setting build_quality (embree_build_quality.hpp). medium (the registry's, Embree's
// default): a single-level SAH BVH rebuilt from the bounds at every commit. high: Embree's
// higher-quality builder (its spatial splits apply to triangle meshes, not to user geometry).
// low: the scene at LOW with the geometry at RTC_BUILD_QUALITY_REFIT (Embree uses the
// per-geometry quality only in LOW's two-level mode), so update() refits the geometry's BVH
// instead of rebuilding it: cheaper updates, a tree that degrades as the boxes move, as any
// refitted one does. All give identical pairs; which is fastest where is the tuning sweep's
// to measure (harness/tuning_sweep.hpp).

// geometryUserPtr of a geometry: the boxes its bounds come from.
void bounds_of(const RTCBoundsFunctionArguments* args) {
    const auto& boxes = *static_cast<const std::span<const collide_box>*>(args->geometryUserPtr);
    const collide_box& b = boxes[args->primID];
    RTCBounds* out = args->bounds_o;
    out->lower_x = spatial::detail_rounding::round_down<float>(b.lo[0]);
    out->lower_y = spatial::detail_rounding::round_down<float>(b.lo[1]);
    out->lower_z = spatial::detail_rounding::round_down<float>(b.lo[2]);
    out->upper_x = spatial::detail_rounding::round_up<float>(b.hi[0]);
    out->upper_y = spatial::detail_rounding::round_up<float>(b.hi[1]);
    out->upper_z = spatial::detail_rounding::round_up<float>(b.hi[2]);
}
// No rays are cast into these scenes; Embree gets no-op ray callbacks so the user geometry
// is complete.
void no_intersect(const RTCIntersectFunctionNArguments*) {}
void no_occluded(const RTCOccludedFunctionNArguments*) {}

struct collide_query {
    std::span<const collide_box> built, others;  // others == built for self pairs
    bool self = true;
    const collide_index::exact_test* exact = nullptr;
    std::vector<index_pair>* out = nullptr;
    std::mutex mutex;
};

// RTCCollideFunc (embree3/rtcore_scene.h: the count is unsigned int in 3.13's header).
void record_collisions(void* user, RTCCollision* collisions, unsigned int count) {
    auto& q = *static_cast<collide_query*>(user);
    const std::lock_guard<std::mutex> lock(q.mutex);
    for (unsigned int c = 0; c < count; ++c) {
        const std::uint32_t i = collisions[c].primID0, j = collisions[c].primID1;
        if (q.self && i >= j) continue;  // (j, i) comes too; (i, i) is skipped by Embree anyway
        if (!closed_boxes_overlap(q.built[i], q.others[j])) continue;
        if (*q.exact && !(*q.exact)(i, j)) continue;
        q.out->emplace_back(i, j);
    }
}

class embree_collide_index final : public collide_index {
public:
    explicit embree_collide_index(RTCBuildQuality quality) : quality_(quality) {}
    ~embree_collide_index() override {
        release();
    }
    embree_collide_index(const embree_collide_index&) = delete;
    embree_collide_index& operator=(const embree_collide_index&) = delete;

    std::string name() const override { return "embree_collide"; }

    void build(std::span<const collide_box> boxes) override {
        release();
        boxes_ = boxes;
        if (boxes_.empty()) return;
        scene_ = make_scene(&boxes_, &geometry_);
    }

    void update(std::span<const collide_box> boxes) override {
        if (boxes.size() != boxes_.size())
            throw std::invalid_argument("embree_collide: update() needs the built boxes' count");
        boxes_ = boxes;  // the bounds callback reads boxes_ through its address
        if (!scene_) return;
        rtcCommitGeometry(geometry_);
        rtcCommitScene(scene_);
        device_.check("rtcCommitScene (update)");
    }

    std::vector<index_pair> self_pairs(const exact_test& exact) override {
        std::vector<index_pair> out;
        if (boxes_.size() < 2) return out;
        collide_query q;
        q.built = q.others = boxes_;
        q.self = true;
        q.exact = &exact;
        q.out = &out;
        rtcCollide(scene_, scene_, &record_collisions, &q);
        device_.check("rtcCollide");
        sort_unique_pairs(out);
        return out;
    }

    std::vector<index_pair> pairs_with(std::span<const collide_box> others, const exact_test& exact) override {
        std::vector<index_pair> out;
        if (boxes_.empty() || others.empty()) return out;
        // rtcCollide needs both sides as scenes of the same device: one over `others`, built
        // for this query (its build is part of the query's cost).
        RTCGeometry other_geometry = nullptr;
        RTCScene other = make_scene(&others, &other_geometry);
        collide_query q;
        q.built = boxes_;
        q.others = others;
        q.self = false;
        q.exact = &exact;
        q.out = &out;
        rtcCollide(scene_, other, &record_collisions, &q);
        const RTCError error = rtcGetDeviceError(device_.get());
        rtcReleaseGeometry(other_geometry);
        rtcReleaseScene(other);
        if (error != RTC_ERROR_NONE) device_.fail("rtcCollide (bipartite)");
        sort_unique_pairs(out);
        return out;
    }

    std::size_t memory_bytes() const override {
        const long long embree = device_.bytes();
        return sizeof(*this) + static_cast<std::size_t>(embree > 0 ? embree : 0);
    }

private:
    // A committed scene with one user geometry over *boxes (the span must outlive the scene's
    // commits). The geometry is returned retained, for later commits.
    RTCScene make_scene(const std::span<const collide_box>* boxes, RTCGeometry* geometry) {
        RTCScene scene = rtcNewScene(device_.get());
        if (!scene) device_.fail("rtcNewScene");
        RTCGeometry g = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_USER);
        if (!g) device_.fail("rtcNewGeometry(USER)");
        rtcSetSceneBuildQuality(scene, quality_);
        if (quality_ == RTC_BUILD_QUALITY_LOW) rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_REFIT);
        rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(boxes->size()));
        rtcSetGeometryUserData(g, const_cast<std::span<const collide_box>*>(boxes));
        rtcSetGeometryBoundsFunction(g, &bounds_of, nullptr);
        rtcSetGeometryIntersectFunction(g, &no_intersect);
        rtcSetGeometryOccludedFunction(g, &no_occluded);
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene, g);
        rtcCommitScene(scene);
        device_.check("rtcCommitScene");
        *geometry = g;
        return scene;
    }
    void release() {
        if (geometry_) rtcReleaseGeometry(geometry_);
        if (scene_) rtcReleaseScene(scene_);
        geometry_ = nullptr;
        scene_ = nullptr;
    }

    RTCBuildQuality quality_;
    embree_device device_{"embree_collide"};
    RTCScene scene_ = nullptr;
    RTCGeometry geometry_ = nullptr;
    std::span<const collide_box> boxes_;  // the caller's (kept alive until the next build/update)
};

}  // namespace

std::unique_ptr<collide_index> make_embree_collide_index(const key_values& settings) {
    return std::make_unique<embree_collide_index>(embree_build_quality(settings, "embree_collide"));
}

}  // namespace harness
