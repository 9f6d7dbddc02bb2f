// FCL 0.7 broad-phase collision managers behind harness::collide_index (declared in
// harness/collide_adapters.hpp).
//
// Compiled with -DEIGEN_MAX_ALIGN_BYTES=16 (harness/adapters/CMakeLists.txt): Debian's
// libfcl is built with 16-byte Eigen alignment, and under -march=native (AVX, AVX-512) Eigen
// would align the Transform3d inside CollisionObjectd, and the code that touches it, to 32 or
// 64 bytes here: the same class with two layouts. No Eigen type crosses this file's boundary.
//
// Objects. Each box is a box_object: an fcl::CollisionObjectd over its own fcl::Boxd, placed
// the way an FCL user would (side hi - lo, translation at the centre (lo + hi) / 2, then
// computeAABB()). computeAABB() gives c -+ side/2, which can differ from lo / hi by a rounding,
// so the object's world AABB (the protected CollisionObject::aabb, which the managers read
// through getAABB() and never recompute) is then overwritten with our box exactly, or grown by
// `grow` (below). user data = the object itself, which carries the index.
//
// Closedness. Every candidate FCL reports goes through closed_boxes_overlap on the double
// boxes (and the caller's exact test), so false candidates never reach the answer. Lost
// candidates are the danger, and depend on the manager:
//   - DynamicAABBTreeCollisionManager tests node AABBs with AABB::overlap, which is closed
//     (fcl/math/bv/AABB-inl.h: disjoint only if min > other.max or max < other.min), and
//     its update() copies getAABB() into the leaves exactly before refitting: exact AABBs,
//     nothing grown.
//   - SaPCollisionManager sorts endpoints with std::less and no tie rule, so where one box's
//     max equals another's min the order, and whether the pair is seen, is arbitrary (touching
//     boxes on an integer grid are lost, measured below).
//   - SpatialHashingCollisionManager puts a box in cells [floor((lo - m) / c), ceil((hi - m)
//     / c)) (fcl/broadphase/detail/spatial_hash-inl.h): boxes touching on a cell boundary
//     share no cell, and a zero-extent box on a boundary is in none. It also reports every
//     pair sharing a hash bucket without any AABB test.
//   For these two, the AABBs handed to FCL are grown by grow = 2^-40 M (M: the largest
//   magnitude of any coordinate, scene limit included, floored at 2^-900). A pair that
//   touches then overlaps by 2 grow > 0, which no tie order can lose; and in the spatial hash,
//   fl(fl(x - m) / c) is within about 2^-51 M / c of (x - m) / c, far below 2 grow / c, so the
//   floor/ceil cell ranges of overlapping grown boxes intersect. The grown boxes overlap a few
//   extra pairs closer than 2 grow; the exact test drops them. (Without the margin, on a 5^3
//   lattice of unit cubes, SaP lost 17 of 1036 contacts and spatial hashing 734.)
//
// SaP's update(). FCL 0.7's SaPCollisionManager::update_ moves an object's endpoints by the
// sign of its lo change on each axis; it is right only if on every axis lo and hi both
// decrease, both increase or both stay. If lo stays and hi moves, hi is left stale; if they
// move apart (a box growing, or our margin changing) it splices an endpoint next to itself and
// the endpoint list becomes a cycle: update() never returns. So update() checks every object
// first (sap_can_follow): translations take FCL's incremental update, anything else rebuilds
// the manager's lists with the bulk registerObjects (not one-by-one registerObject, which
// misses a box enclosing the new one on the sweep axis). Costs measured here, not ours to
// fix: FCL's SaP build and incremental update grow roughly as n^1.8-2 (1e5 boxes: 4.9 s and
// 21 s; addToOverlapPairs scans the whole pair list), and its bipartite collide walks the
// endpoint list from its start for every query object, O(n m).
//
// Spatial hashing parameters (FCL requires them up front): cell size c = 2 x the median of the
// boxes' largest extents (a median, so one huge box does not inflate it), but at least the
// scene's longest side / (4 cbrt(n) + 1), which caps the cell count at about 64 n so that a
// huge box is hashed into O(n) cells, not O((side / c)^3); scene limits = the boxes' bounds
// grown by one cell, and the bucket table max(1000 (FCL's default), min(cells, 2n)). With all
// boxes inside the limits FCL hashes them all; when update() moves a box out of the limits,
// the manager is rebuilt with new limits rather than left to FCL's outside-the-limits lists
// (which compare every outside object with every other, and whose clipped cell ranges could
// be empty). FCL's own update() rehashes every object, so the rebuild is the same O(n) order.

#include <fcl/broadphase/broadphase_SaP.h>
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/broadphase/broadphase_spatialhash.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <list>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "harness/collide_adapters.hpp"

// Eigen defines EIGEN_MAX_ALIGN_BYTES itself when it is not given (32 or 64 under AVX/AVX-512).
#if EIGEN_MAX_ALIGN_BYTES != 16
#error "fcl_collide_index.cpp must be compiled with -DEIGEN_MAX_ALIGN_BYTES=16 (Debian's libfcl ABI)"
#endif

namespace harness {
namespace {

using spatial_hash_manager = fcl::SpatialHashingCollisionManagerd<>;

// A CollisionObjectd whose world AABB we set (CollisionObject::aabb is protected).
class box_object final : public fcl::CollisionObjectd {
public:
    box_object(const std::shared_ptr<fcl::Boxd>& shape, std::uint32_t index, bool in_others)
        : fcl::CollisionObjectd(shape), shape_(shape.get()), index_(index), in_others_(in_others) {
        setUserData(this);
    }

    // The Box shape and transform as an FCL user would set them, then the exact AABB (grown
    // by `grow` on every side; grow = 0 for the managers that need nothing else).
    void place(const collide_box& b, double grow) {
        shape_->side = fcl::Vector3d(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]);
        shape_->computeLocalAABB();
        setTranslation(fcl::Vector3d(0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1]), 0.5 * (b.lo[2] + b.hi[2])));
        computeAABB();
        aabb.min_ = fcl::Vector3d(b.lo[0] - grow, b.lo[1] - grow, b.lo[2] - grow);
        aabb.max_ = fcl::Vector3d(b.hi[0] + grow, b.hi[1] + grow, b.hi[2] + grow);
    }
    std::uint32_t index() const { return index_; }
    bool in_others() const { return in_others_; }

private:
    fcl::Boxd* shape_;
    std::uint32_t index_;
    bool in_others_;
};

// The per-object bytes of SaP's endpoint structures (protected nested types, sized here).
struct sap_sizes : fcl::SaPCollisionManagerd {
    static constexpr std::size_t per_object = sizeof(SaPAABB) + 2 * sizeof(EndPoint) + 6 * sizeof(EndPoint*);
};

double largest_magnitude(std::span<const collide_box> boxes) {
    double m = 0;
    for (const collide_box& b : boxes)
        for (std::size_t k = 0; k < 3; ++k) m = std::max({m, std::abs(b.lo[k]), std::abs(b.hi[k])});
    return m;
}
double grow_for(double magnitude) {
    return std::max(0x1p-40 * magnitude, 0x1p-900);
}

struct hash_parameters {
    double cell = 1;
    fcl::Vector3d lo = fcl::Vector3d::Zero(), hi = fcl::Vector3d::Zero();
    std::size_t table_size = 1000;
};

hash_parameters spatial_hash_parameters_for(std::span<const collide_box> boxes) {
    hash_parameters p;
    if (boxes.empty()) return p;
    std::vector<double> extents(boxes.size());
    double span = 0;
    for (std::size_t k = 0; k < 3; ++k) {
        p.lo[static_cast<int>(k)] = std::numeric_limits<double>::infinity();
        p.hi[static_cast<int>(k)] = -std::numeric_limits<double>::infinity();
    }
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        double e = 0;
        for (int k = 0; k < 3; ++k) {
            const auto uk = static_cast<std::size_t>(k);
            e = std::max(e, boxes[i].hi[uk] - boxes[i].lo[uk]);
            p.lo[k] = std::min(p.lo[k], boxes[i].lo[uk]);
            p.hi[k] = std::max(p.hi[k], boxes[i].hi[uk]);
        }
        extents[i] = e;
    }
    for (int k = 0; k < 3; ++k) span = std::max(span, p.hi[k] - p.lo[k]);
    auto middle = extents.begin() + static_cast<std::ptrdiff_t>(extents.size() / 2);
    std::nth_element(extents.begin(), middle, extents.end());
    const double n = static_cast<double>(boxes.size());
    // The last term keeps the cell far above the grow margin, so grown boxes stay inside.
    p.cell = std::max({2 * *middle, span / (4 * std::cbrt(n) + 1), 0x1p-30 * largest_magnitude(boxes)});
    if (!(p.cell > 0) || !std::isfinite(p.cell)) p.cell = 1;  // all boxes one point at 0, or overflow
    double cells = 1;
    for (int k = 0; k < 3; ++k) {
        p.lo[k] -= p.cell;
        p.hi[k] += p.cell;
        cells *= std::ceil((p.hi[k] - p.lo[k]) / p.cell);
    }
    p.table_size = static_cast<std::size_t>(std::max(1000.0, std::min(cells, 2 * n)));
    return p;
}

// One manager and the objects registered in it.
class object_set {
public:
    object_set(fcl_manager_kind kind, std::span<const collide_box> boxes, bool in_others) : kind_(kind) {
        objects_.reserve(boxes.size());
        for (std::size_t i = 0; i < boxes.size(); ++i)
            objects_.push_back(std::make_unique<box_object>(std::make_shared<fcl::Boxd>(0.0, 0.0, 0.0),
                                                            static_cast<std::uint32_t>(i), in_others));
        make_manager(boxes);
    }

    void update(std::span<const collide_box> boxes) {
        if (boxes.size() != objects_.size()) throw std::invalid_argument("fcl: update() needs the built boxes' count");
        switch (kind_) {
            case fcl_manager_kind::dynamic_aabb_tree:
                break;
            case fcl_manager_kind::sap:
                if (grow_ < grow_for(largest_magnitude(boxes)) * 0x1p-5) {
                    make_manager(boxes);  // coordinates grew 32x: the margin would round away
                    return;
                }
                if (!sap_can_follow(boxes)) {
                    // See the file comment: FCL's SaP update would corrupt its lists; rebuild
                    // them with the bulk registration (an O(n log n) sort and sweep).
                    place_all(boxes);
                    manager_->clear();
                    register_all();
                    return;
                }
                break;
            case fcl_manager_kind::spatial_hashing:
                if (!inside_limits(boxes)) {
                    make_manager(boxes);  // see the file comment: new scene limits
                    return;
                }
                break;
        }
        place_all(boxes);
        manager_->update();
    }

    fcl::BroadPhaseCollisionManagerd& manager() const { return *manager_; }

    std::size_t memory_bytes() const {
        const std::size_t n = objects_.size();
        // make_shared puts the Box and its control block (two counts and a vtable) together.
        std::size_t bytes = sizeof(*this) + objects_.capacity() * sizeof(objects_[0]) +
                            n * (sizeof(box_object) + sizeof(fcl::Boxd) + 2 * sizeof(void*));
        switch (kind_) {
            case fcl_manager_kind::dynamic_aabb_tree:
                bytes += sizeof(fcl::DynamicAABBTreeCollisionManagerd) +
                         (n > 0 ? 2 * n - 1 : 0) * sizeof(fcl::detail::NodeBase<fcl::AABBd>);
                break;
            case fcl_manager_kind::sap:
                bytes += sizeof(fcl::SaPCollisionManagerd) + n * sap_sizes::per_object;
                break;
            case fcl_manager_kind::spatial_hashing:
                bytes += sizeof(spatial_hash_manager) + hash_.table_size * sizeof(std::list<fcl::CollisionObjectd*>);
                break;
        }
        return bytes;
    }

private:
    void make_manager(std::span<const collide_box> boxes) {
        double magnitude = largest_magnitude(boxes);
        switch (kind_) {
            case fcl_manager_kind::dynamic_aabb_tree:
                grow_ = 0;
                manager_ = std::make_unique<fcl::DynamicAABBTreeCollisionManagerd>();
                break;
            case fcl_manager_kind::sap:
                grow_ = grow_for(magnitude);
                manager_ = std::make_unique<fcl::SaPCollisionManagerd>();
                break;
            case fcl_manager_kind::spatial_hashing:
                hash_ = spatial_hash_parameters_for(boxes);
                magnitude = std::max({magnitude, hash_.lo.cwiseAbs().maxCoeff(), hash_.hi.cwiseAbs().maxCoeff()});
                grow_ = grow_for(magnitude);
                manager_ = std::make_unique<spatial_hash_manager>(hash_.cell, hash_.lo, hash_.hi,
                                                                  static_cast<unsigned>(hash_.table_size));
                break;
        }
        place_all(boxes);
        register_all();
    }
    // Bulk registration: FCL's one-by-one registerObject path is slower, and SaP's misses a
    // box whose interval encloses the new one on the sweep axis.
    void register_all() {
        std::vector<fcl::CollisionObjectd*> raw(objects_.size());
        for (std::size_t i = 0; i < objects_.size(); ++i) raw[i] = objects_[i].get();
        manager_->registerObjects(raw);
        manager_->setup();
    }
    void place_all(std::span<const collide_box> boxes) {
        for (std::size_t i = 0; i < boxes.size(); ++i) objects_[i]->place(boxes[i], grow_);
    }
    // True if FCL's SaP update_ can follow every object (see the file comment): on each axis
    // the grown lo and hi change with the same sign. Translations do; resizes may not. O(n).
    bool sap_can_follow(std::span<const collide_box> boxes) const {
        auto sign = [](double d) { return (d > 0) - (d < 0); };
        for (std::size_t i = 0; i < boxes.size(); ++i) {
            const fcl::AABBd& old = objects_[i]->getAABB();
            for (int k = 0; k < 3; ++k) {
                const auto uk = static_cast<std::size_t>(k);
                if (sign((boxes[i].lo[uk] - grow_) - old.min_[k]) != sign((boxes[i].hi[uk] + grow_) - old.max_[k]))
                    return false;
            }
        }
        return true;
    }
    // Every grown box strictly inside the spatial hash's scene limits.
    bool inside_limits(std::span<const collide_box> boxes) const {
        for (const collide_box& b : boxes)
            for (int k = 0; k < 3; ++k) {
                const auto uk = static_cast<std::size_t>(k);
                if (!(b.lo[uk] - grow_ > hash_.lo[k] && b.hi[uk] + grow_ < hash_.hi[k])) return false;
            }
        return true;
    }

    fcl_manager_kind kind_;
    std::vector<std::unique_ptr<box_object>> objects_;  // stable addresses: FCL keeps pointers
    std::unique_ptr<fcl::BroadPhaseCollisionManagerd> manager_;
    double grow_ = 0;
    hash_parameters hash_;
};

// What the callback needs; FCL hands it back as void*.
struct query_context {
    std::span<const collide_box> built, others;  // others == built for self pairs
    bool self = true;
    const collide_index::exact_test* exact = nullptr;
    std::vector<index_pair>* out = nullptr;
};

// FCL's CollisionCallBack: a plain function pointer; returning true would stop the traversal.
bool record_pair(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
    const auto& q = *static_cast<const query_context*>(data);
    const auto* a = static_cast<const box_object*>(o1->getUserData());
    const auto* b = static_cast<const box_object*>(o2->getUserData());
    if (a->in_others()) std::swap(a, b);  // bipartite managers may call back in either order
    std::uint32_t i = a->index(), j = b->index();
    if (q.self) {
        if (i == j) return false;
        if (i > j) std::swap(i, j);
    }
    if (!closed_boxes_overlap(q.built[i], q.others[j])) return false;
    if (*q.exact && !(*q.exact)(i, j)) return false;
    q.out->emplace_back(i, j);
    return false;
}

class fcl_collide_index final : public collide_index {
public:
    explicit fcl_collide_index(fcl_manager_kind kind) : kind_(kind) {}

    std::string name() const override {
        switch (kind_) {
            case fcl_manager_kind::dynamic_aabb_tree:
                return "fcl_dynamic_aabb_tree";
            case fcl_manager_kind::sap:
                return "fcl_sap";
            case fcl_manager_kind::spatial_hashing:
                return "fcl_spatial_hashing";
        }
        return "fcl";
    }

    void build(std::span<const collide_box> boxes) override {
        boxes_ = boxes;
        set_ = std::make_unique<object_set>(kind_, boxes, false);
    }
    void update(std::span<const collide_box> boxes) override {
        if (!set_) throw std::logic_error("fcl: update() before build()");
        set_->update(boxes);
        boxes_ = boxes;
    }

    std::vector<index_pair> self_pairs(const exact_test& exact) override {
        std::vector<index_pair> out;
        if (!set_ || boxes_.size() < 2) return out;
        query_context q{boxes_, boxes_, true, &exact, &out};
        set_->manager().collide(&q, &record_pair);
        sort_unique_pairs(out);
        return out;
    }

    std::vector<index_pair> pairs_with(std::span<const collide_box> others, const exact_test& exact) override {
        std::vector<index_pair> out;
        if (!set_ || boxes_.empty() || others.empty()) return out;
        const object_set other_set(kind_, others, true);
        query_context q{boxes_, others, false, &exact, &out};
        set_->manager().collide(&other_set.manager(), &q, &record_pair);
        sort_unique_pairs(out);
        return out;
    }

    std::size_t memory_bytes() const override { return sizeof(*this) + (set_ ? set_->memory_bytes() : 0); }

private:
    fcl_manager_kind kind_;
    std::span<const collide_box> boxes_;  // the caller's (kept alive until the next build/update)
    std::unique_ptr<object_set> set_;
};

}  // namespace

std::unique_ptr<collide_index> make_fcl_collide_index(fcl_manager_kind kind) {
    return std::make_unique<fcl_collide_index>(kind);
}

}  // namespace harness
