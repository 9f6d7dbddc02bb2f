// Embree 3 behind harness::ray_index<T> (see harness/ray_adapters.hpp for the contract).
//
// Embree (Wald et al., "Embree: A Kernel Framework for Efficient CPU Ray Tracing", ACM TOG
// 2014) builds a BVH with SAH binning and traverses it with SIMD; it works in float only.
// Configuration, chosen to compare like with like:
//   * one device per index with "threads=1": our builders are single-threaded, and the
//     machine (2 cores) is shared; queries are single rays (rtcIntersect1 / rtcOccluded1);
//   * settings (harness/peer_registry.hpp, tuning_sweep.hpp): build_quality low | medium |
//     high (embree_build_quality.hpp; the registry's medium is Embree's default, and the
//     tuning sweep runs the other two: high's spatial splits build slower for fewer
//     overlapping nodes, low builds fastest), set on the scene and the geometry (Embree
//     reads the geometry's only in low's two-level mode); flags: absent ("embree", default
//     scene flags) or robust (RTC_SCENE_FLAG_ROBUST, "embree_robust": "avoid optimizations
//     that reduce arithmetic accuracy"), whose price and effect on leaks at shared edges the
//     suite measures;
//   * shared buffers: Embree reads the caller's index triples in place; only the vertices
//     are converted (to float, padded by one float because Embree loads vertices with 16-byte
//     SIMD reads).

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/ray_adapters.hpp"
#include "harness/tuning_sweep.hpp"
#include "embree_build_quality.hpp"
#include "embree_device.hpp"

namespace harness {
namespace {

template <class T>
class embree_ray_index final : public ray_index<T> {
public:
    using typename ray_index<T>::point_type;
    using typename ray_index<T>::triangle_type;

    embree_ray_index(bool robust, RTCBuildQuality quality) : robust_(robust), quality_(quality) {}
    ~embree_ray_index() override {
        release_scene();
    }
    embree_ray_index(const embree_ray_index&) = delete;
    embree_ray_index& operator=(const embree_ray_index&) = delete;

    std::string name() const override { return robust_ ? "embree_robust" : "embree"; }

    void build(const datasets::triangle_mesh& mesh, std::span<const triangle_type>) override {
        release_scene();
        vertices_.assign(3 * mesh.vertices.size() + 1, 0.0f);
        for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
            for (std::size_t d = 0; d < 3; ++d) vertices_[3 * i + d] = static_cast<float>(mesh.vertices[i][d]);
        index_bytes_ = mesh.triangles.size() * sizeof(datasets::triangle_mesh::index_triple);
        size_ = mesh.triangles.size();

        scene_ = rtcNewScene(device_.get());
        if (!scene_) device_.fail("rtcNewScene");
        if (robust_) rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(scene_, quality_);
        if (size_ > 0) {
            RTCGeometry geometry = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
            if (!geometry) device_.fail("rtcNewGeometry");
            rtcSetGeometryBuildQuality(geometry, quality_);
            rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices_.data(), 0,
                                       3 * sizeof(float), mesh.vertices.size());
            rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.triangles.data(), 0,
                                       sizeof(datasets::triangle_mesh::index_triple), mesh.triangles.size());
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene_, geometry);
            rtcReleaseGeometry(geometry);  // the scene holds it
        }
        rtcCommitScene(scene_);
        device_.check("rtcCommitScene");
    }
    std::size_t size() const override { return size_; }
    std::size_t memory_bytes() const override {
        const long long embree = device_.bytes();
        return sizeof(*this) + static_cast<std::size_t>(embree > 0 ? embree : 0) + vertices_.capacity() * sizeof(float) +
               index_bytes_;
    }

    bool intersect(const point_type& origin, const point_type& direction, T t_max, ray_hit<T>& hit) override {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh;
        set_ray(rh.ray, origin, direction, t_max);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
        // tfar was min(t_max, float) on entry, so a hit has tfar < t_max up to rounding.
        const T t = static_cast<T>(rh.ray.tfar);
        if (!(t < t_max)) return false;
        hit.t = t;
        hit.triangle = rh.hit.primID;
        return true;
    }

    bool occluded(const point_type& origin, const point_type& direction, T t_max) override {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRay ray;
        set_ray(ray, origin, direction, t_max);
        rtcOccluded1(scene_, &context, &ray);
        return ray.tfar == -std::numeric_limits<float>::infinity();  // Embree's "occluded" mark
    }

private:
    static void set_ray(RTCRay& ray, const point_type& o, const point_type& d, T t_max) {
        ray.org_x = static_cast<float>(o[0]);
        ray.org_y = static_cast<float>(o[1]);
        ray.org_z = static_cast<float>(o[2]);
        ray.dir_x = static_cast<float>(d[0]);
        ray.dir_y = static_cast<float>(d[1]);
        ray.dir_z = static_cast<float>(d[2]);
        ray.tnear = 0.0f;
        // Largest float <= t_max, so Embree never reports a hit beyond the caller's bound.
        float far = static_cast<float>(t_max);
        if (static_cast<T>(far) > t_max) far = std::nextafter(far, -std::numeric_limits<float>::infinity());
        ray.tfar = far;
        ray.time = 0.0f;
        ray.mask = ~0u;  // -1: every geometry
        ray.id = 0;
        ray.flags = 0;
    }
    void release_scene() {
        if (scene_) rtcReleaseScene(scene_);
        scene_ = nullptr;
    }

    bool robust_;
    RTCBuildQuality quality_;
    embree_device device_{"embree"};
    RTCScene scene_ = nullptr;
    std::vector<float> vertices_;
    std::size_t index_bytes_ = 0;
    std::size_t size_ = 0;
};

}  // namespace

template <class T>
std::unique_ptr<ray_index<T>> make_embree_ray_index(const key_values& settings) {
    // flags: the registry line of embree_robust has flags=robust; embree's has none.
    bool robust = false;
    for (const auto& [key, value] : settings)
        if (key == "flags") {
            if (value != "robust")
                throw std::invalid_argument("embree_robust: setting flags=" + value + " is not robust");
            robust = true;
        }
    return std::make_unique<embree_ray_index<T>>(robust,
                                                 embree_build_quality(settings, robust ? "embree_robust" : "embree"));
}

template std::unique_ptr<ray_index<float>> make_embree_ray_index<float>(const key_values&);
template std::unique_ptr<ray_index<double>> make_embree_ray_index<double>(const key_values&);

}  // namespace harness
