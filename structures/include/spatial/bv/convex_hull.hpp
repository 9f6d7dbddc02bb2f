#pragma once
// spatial::convex_hull<T, D> — the tightest convex bounding volume: the convex hull of the
// points, stored as its vertices (exact input points), its facet planes (outward unit normal
// + offset, relative to a reference point) and, in 3D, an outward-oriented triangulated
// surface.
//
// Fitting (fit_quickhull, alias fit):
//   3D: Quickhull (Barber, Dobkin & Huhdanpaa 1996) with conflict lists, farthest point
//       first and the horizon by depth-first search over facet adjacency (quickhull_3d.hpp).
//       O(n log r) expected, O(n log n) when all points are vertices.
//   2D: Andrew's monotone chain (hull_2d.hpp), O(n log n); Quickhull's 2D case would give
//       the same hull and no better bound on adversarial input.
//   Both use orientation tests with an exact sign (predicates.hpp), so the hull is the EXACT
//   convex hull of the input floats/doubles: its vertices are exactly the extreme input points
//   (points on an edge or facet are not vertices), and the 3D surface is always closed,
//   consistently oriented, every edge in exactly two triangles, V - E + F = 2. Coplanar
//   adjacent triangles (an exactly planar face, e.g. a cube's side) share one plane.
//   Why exact rather than qhull's thick-plane epsilon tests: epsilon tests need facet
//   merging to keep the topology valid; exact signs make invalid topology impossible at
//   the cost of a fallback that only near-degenerate input triggers.
//
// Degenerate input (decided exactly; documented because every BV must handle it):
//   no points   -> the empty hull (contains nothing, merge identity).
//   all equal   -> one vertex; affine_dimension() 0; planes +-e_i with offset 0.
//   collinear   -> the two extreme points (dimension 1); planes: +- the segment direction
//                  and +- D-1 unit perpendiculars (a thin box around the segment).
//   coplanar 3D -> the polygon (dimension 2), vertices in counter-clockwise order about the
//                  polygon normal, triangles() a closed double-covered fan (2(k - 2)
//                  triangles, V - E + F = 2); planes +- the normal and one in-plane side
//                  plane per edge.
//   off the grid -> a coordinate the exact predicates cannot square without underflow (a
//                  denormal; below about 5e-87 and not a multiple of 2^-340; predicates.hpp):
//                  the hull of the points' bounding box rounded outward onto that grid, which
//                  contains every point but is not the exact hull.
//   volume() is 0 for every flat hull, never NaN. surface_area() of a flat hull is the
//   limit of a thin slab's: twice the polygon's area (3D), twice the segment's length (2D).
//
// Precision: planes are stored relative to reference() (the centre of the vertices' box),
// computed in double, normals rounded to T and offsets rounded up as the maximum over the
// vertices (found by hill climbing on the vertex graph) of normal . (v - reference()).
// contains(p) accepts p when normal . (p - reference()) <= offset + tolerance() for every
// plane, with tolerance() = 8 D eps_T R1, R1 = max over vertices of |v - reference()|_1 (a
// few ulps of the hull's extent; 0 for a single point): every input point is contained,
// at any offset (1e8) or spread (1e-12). ray_interval() uses the same thickened planes.
//
// Queries (V vertices, F planes):
//   contains            O(F), early exit.
//   ray_interval        O(F), Cyrus & Beck 1978 clipping of the line against the planes;
//                       zero and negative-zero direction components handled without NaN.
//   distance_lower_bound O(F): max over planes of the signed plane distance, minus the
//                       tolerance and rounding, clamped at 0 (each plane bounds the hull).
//   overlaps            GJK (Gilbert, Johnson & Keerthi 1988; gjk.hpp) on the two vertex
//                       sets, exact up to a tolerance of tolerance() of both hulls plus the
//                       rounding of the coordinates: it returns false only when a separating
//                       direction with a larger gap is certified on the actual vertices, so
//                       there are no false negatives (touching hulls overlap). When GJK
//                       stalls at a tiny positive distance (parallel features nearly
//                       touching), a separating-axis pass over both hulls' facet normals
//                       decides. Support points by hill climbing on the vertex graph
//                       (O(sqrt V)-ish per support on round hulls), linear scan for V <= 32;
//                       a box test first. Typical cost O(iterations * support).
//   merged              the hull of both vertex sets (exact).
//   transformed         moves vertices and planes (no refit, O(V + F)); the tolerance grows
//                       by the rounding of the motion so the result contains the moved hull.
//   volume              divergence theorem over the triangles (3D) / shoelace (2D), in
//                       double relative to reference().

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <unordered_set>
#include <vector>

#include "spatial/bv/bounding_volume.hpp"
#include "spatial/bv/gjk.hpp"
#include "spatial/bv/hull_2d.hpp"
#include "spatial/bv/predicates.hpp"
#include "spatial/bv/rounding.hpp"
#include "spatial/bv/quickhull_3d.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/rigid_transform.hpp"

namespace spatial {

template <class T, std::size_t D>
class convex_hull {
    static_assert(D == 2 || D == 3, "convex_hull<T, D>: D must be 2 or 3");

public:
    SPATIAL_POINT_MEMBER_TYPES(T, D);
    using index_type = std::uint32_t;
    using triangle = std::array<index_type, 3>;
    // Half-space normal . (x - reference()) <= offset (+ tolerance()); |normal| = 1 up to
    // rounding to T.
    struct plane {
        std::array<T, D> normal;
        T offset;
    };

    convex_hull() = default;  // the empty hull
    static convex_hull empty() { return {}; }
    bool is_empty() const { return vertices_.empty(); }

    // The exact convex hull of pts (see the header comment). Throws std::invalid_argument on
    // NaN or infinite coordinates.
    static convex_hull fit_quickhull(std::span<const point_type> pts) {
        for (const auto& p : pts) detail::require_finite(p, "convex_hull::fit_quickhull", "input point");
        convex_hull h;
        if (pts.empty()) return h;
        if (off_exact_grid(pts)) return fit_quickhull(grid_box_corners(pts));
        if constexpr (D == 2) {
            const auto idx = hull_2d_indices(pts.size(), [&](std::size_t i) {
                return std::array<double, 2>{double(pts[i][0]), double(pts[i][1])};
            });
            for (std::size_t i : idx) h.vertices_.push_back(pts[i]);
            h.dim_ = idx.size() >= 3 ? 2 : static_cast<int>(idx.size()) - 1;
            h.finish({}, 0);
        } else {
            std::vector<std::array<double, 3>> q(pts.size());
            for (std::size_t i = 0; i < pts.size(); ++i) q[i] = {double(pts[i][0]), double(pts[i][1]), double(pts[i][2])};
            auto r = quickhull_3d(q);
            h.dim_ = r.dimension;
            if (r.dimension == 3 && r.vertices.size() > 4096) spatial_order(r, q);
            std::vector<index_type> remap(pts.size(), none);
            for (index_type v : r.vertices) {
                remap[v] = static_cast<index_type>(h.vertices_.size());
                h.vertices_.push_back(pts[v]);
            }
            h.triangles_.resize(r.triangles.size());
            for (std::size_t t = 0; t < r.triangles.size(); ++t)
                for (int k = 0; k < 3; ++k) h.triangles_[t][k] = remap[r.triangles[t][k]];
            h.finish(r.faces, r.face_count);
        }
        return h;
    }
    static convex_hull fit(std::span<const point_type> pts) { return fit_quickhull(pts); }

private:
    // Points off the exact predicates' grid (predicates.hpp: a denormal, or any number below
    // about 5e-87 that is not a multiple of 2^-340) would make Quickhull's signs inexact, and it
    // then built wrong hulls or read past its lists (found by fuzzing, docs/fuzzing.md). Such
    // input is fitted by the hull of its bounding box rounded outward onto the grid: it contains
    // every point, and is no longer the exact hull. Coordinates beyond 2^300 (about 2e90) have
    // no grid box and stay outside the guarantee (float never reaches either limit).
    static bool off_exact_grid(std::span<const point_type> pts) {
        bool off = false;
        for (const auto& p : pts)
            for (std::size_t i = 0; i < D; ++i) {
                const double x = static_cast<double>(p[i]);
                if (!(std::abs(x) <= predicates::exact_limit)) return false;
                off = off || !predicates::on_exact_grid(x);
            }
        return off;
    }
    static std::vector<point_type> grid_box_corners(std::span<const point_type> pts) {
        std::array<double, D> lo, hi;
        lo.fill(std::numeric_limits<double>::infinity());
        hi.fill(-std::numeric_limits<double>::infinity());
        for (const auto& p : pts)
            for (std::size_t i = 0; i < D; ++i)
                lo[i] = std::min(lo[i], static_cast<double>(p[i])), hi[i] = std::max(hi[i], static_cast<double>(p[i]));
        std::vector<point_type> corners(std::size_t(1) << D);
        for (std::size_t m = 0; m < corners.size(); ++m)
            for (std::size_t i = 0; i < D; ++i)
                corners[m][i] = static_cast<T>((m >> i) & 1 ? predicates::to_exact_grid(hi[i], false)
                                                            : predicates::to_exact_grid(lo[i], true));
        return corners;
    }

public:

    // The hull's vertices: input points, exactly. 2D and flat 3D hulls: counter-clockwise.
    std::span<const point_type> vertices() const { return vertices_; }
    std::span<const plane> planes() const { return planes_; }
    // 3D: outward (counter-clockwise from outside) triangles indexing vertices(); a closed
    // surface for dimension >= 2, empty below. 2D: empty (the polygon is vertices()).
    std::span<const triangle> triangles() const { return triangles_; }
    // 3D: number of triangles. 2D: number of polygon edges (1 for a segment, 0 for a point).
    std::size_t facet_count() const {
        if constexpr (D == 3) return triangles_.size();
        else return dim_ == 2 ? vertices_.size() : (dim_ == 1 ? 1 : 0);
    }
    int affine_dimension() const { return dim_; }  // -1 empty, 0 point, 1 segment, 2, 3
    const point_type& reference() const { return ref_; }
    T tolerance() const { return tol_; }

    bool contains(const point_type& p) const {
        if (is_empty()) return false;
        std::array<T, D> q;
        for (std::size_t i = 0; i < D; ++i) q[i] = p[i] - ref_[i];
        for (const plane& h : planes_) {
            T s = 0;
            for (std::size_t i = 0; i < D; ++i) s += h.normal[i] * q[i];
            if (s > h.offset + tol_) return false;
        }
        return true;
    }

    // Cyrus-Beck: intersect the parameter intervals of the line o + t d in every thickened
    // half-space. A component of n . d that is (negative) zero means the line is parallel
    // to that plane: inside it for all t or for none; no division happens then. `grow`
    // pushes every plane out by that much more (a thick ray's radius: bvh/node_volume.hpp).
    bool ray_interval(const point_type& o, const point_type& d, T& t0, T& t1, T grow = 0) const {
        if (is_empty()) return false;
        T lo = -std::numeric_limits<T>::infinity(), hi = std::numeric_limits<T>::infinity();
        const T push = tol_ + grow;
        std::array<T, D> q;
        for (std::size_t i = 0; i < D; ++i) q[i] = o[i] - ref_[i];
        for (const plane& h : planes_) {
            T nq = 0, nd = 0;
            for (std::size_t i = 0; i < D; ++i) nq += h.normal[i] * q[i], nd += h.normal[i] * d[i];
            const T room = h.offset + push - nq;  // >= 0 iff o is inside this half-space
            if (nd == 0) {
                if (room < 0) return false;
                continue;
            }
            const T t = room / nd;
            if (nd > 0) hi = std::min(hi, t);
            else lo = std::max(lo, t);
            if (lo > hi) return false;
        }
        t0 = lo;
        t1 = hi;
        return true;
    }

    // Largest signed distance to a facet plane (each plane bounds the hull), minus the
    // tolerance and the evaluation's rounding, clamped at 0. +infinity for the empty hull.
    T distance_lower_bound(const point_type& p) const {
        if (is_empty()) return std::numeric_limits<T>::infinity();
        std::array<T, D> q;
        T q1 = 0;
        for (std::size_t i = 0; i < D; ++i) q[i] = p[i] - ref_[i], q1 += std::abs(q[i]);
        T best = -std::numeric_limits<T>::infinity();
        for (const plane& h : planes_) {
            T s = 0;
            for (std::size_t i = 0; i < D; ++i) s += h.normal[i] * q[i];
            best = std::max(best, s - h.offset);
        }
        constexpr T eps = std::numeric_limits<T>::epsilon();
        const T slack = tol_ + T(2 * (D + 1)) * eps * (q1 + T(radius1_));
        const T r = (best - slack) * (1 - T(4 * D) * eps);  // |normal| may exceed 1 by rounding
        return r > 0 ? r : T(0);
    }

    // GJK on the vertex sets (see the header comment); a box test first.
    bool overlaps(const convex_hull& o) const {
        if (is_empty() || o.is_empty()) return false;
        const double tol = double(tol_) + double(o.tol_);
        for (std::size_t i = 0; i < D; ++i)
            if (double(o.lo_[i]) - double(hi_[i]) > tol || double(lo_[i]) - double(o.hi_[i]) > tol) return false;
        std::array<double, D> delta;  // reference() - o.reference()
        double delta1 = 0;
        for (std::size_t i = 0; i < D; ++i) delta[i] = double(ref_[i]) - double(o.ref_[i]), delta1 += std::abs(delta[i]);
        index_type hint_a = 0, hint_b = 0;
        auto support_a = [&](const std::array<double, D>& dir) {
            hint_a = support_index(dir, hint_a);
            std::array<double, D> x;
            for (std::size_t i = 0; i < D; ++i) x[i] = (double(vertices_[hint_a][i]) - double(ref_[i])) + delta[i];
            return x;
        };
        auto support_b = [&](const std::array<double, D>& dir) {
            hint_b = o.support_index(dir, hint_b);
            std::array<double, D> x;
            for (std::size_t i = 0; i < D; ++i) x[i] = double(o.vertices_[hint_b][i]) - double(o.ref_[i]);
            return x;
        };
        // The rounding of the support points' coordinates (and of delta) joins the tolerance.
        const double slack = tol + 16 * std::numeric_limits<double>::epsilon() * (radius1_ + o.radius1_ + delta1);
        const gjk_outcome r = gjk_classify<D>(support_a, support_b, delta, slack);
        if (r != gjk_outcome::undecided) return r == gjk_outcome::intersect;
        // GJK stalled at a tiny positive distance (nearly touching, parallel features): the
        // facet planes' normals are accurate axes (separating-axis test over the face normals
        // of both hulls; an edge-edge axis is a facet normal of the Minkowski difference,
        // which GJK already tried). Only near-contact pairs get here.
        std::array<double, D> back;  // o.reference() - reference()
        for (std::size_t i = 0; i < D; ++i) back[i] = -delta[i];
        return !face_axis_separates(o, delta, slack) && !o.face_axis_separates(*this, back, slack);
    }

    // The exact hull of both vertex sets; its tolerance is at least both inputs'.
    convex_hull merged(const convex_hull& o) const {
        if (is_empty()) return o;
        if (o.is_empty()) return *this;
        std::vector<point_type> all(vertices_.begin(), vertices_.end());
        all.insert(all.end(), o.vertices_.begin(), o.vertices_.end());
        convex_hull m = fit_quickhull(all);
        m.tol_ = std::max({m.tol_, tol_, o.tol_});
        return m;
    }

    // Moves vertices (v' = R (v - ref) + R ref + t, in double, rounded to T) and planes
    // (normals rotated, offsets kept, relative to the moved reference point); the tolerance
    // grows by a bound on the rounding of all that and on R's deviation from orthonormality,
    // so the result contains the moved hull. O(V + F); triangles and adjacency are shared.
    convex_hull transformed(const rigid_transform<T, D>& xf) const {
        if (is_empty()) return *this;
        convex_hull h = *this;
        double r[D][D];
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) r[i][j] = double(xf.rotation[i][j]);
        double eta = 0;  // max |(R^T R - I)_ij|
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) {
                double s = i == j ? -1.0 : 0.0;
                for (std::size_t k = 0; k < D; ++k) s += r[k][i] * r[k][j];
                eta = std::max(eta, std::abs(s));
            }
        std::array<double, D> ref_moved;
        for (std::size_t i = 0; i < D; ++i) {
            double s = double(xf.translation[i]);
            for (std::size_t j = 0; j < D; ++j) s += r[i][j] * double(ref_[j]);
            ref_moved[i] = s;
        }
        for (std::size_t i = 0; i < D; ++i) h.ref_[i] = T(ref_moved[i]);
        for (std::size_t v = 0; v < vertices_.size(); ++v) {
            std::array<double, D> rel;
            for (std::size_t j = 0; j < D; ++j) rel[j] = double(vertices_[v][j]) - double(ref_[j]);
            for (std::size_t i = 0; i < D; ++i) {
                double s = ref_moved[i];
                for (std::size_t j = 0; j < D; ++j) s += r[i][j] * rel[j];
                h.vertices_[v][i] = T(s);
            }
        }
        for (plane& pl : h.planes_) {
            std::array<double, D> n{};
            for (std::size_t i = 0; i < D; ++i)
                for (std::size_t j = 0; j < D; ++j) n[i] += r[i][j] * double(pl.normal[j]);
            for (std::size_t i = 0; i < D; ++i) pl.normal[i] = T(n[i]);
        }
        h.update_box_and_radius();
        double ref1 = 0;
        for (std::size_t i = 0; i < D; ++i) ref1 += std::abs(ref_moved[i]);
        constexpr double eps = std::numeric_limits<T>::epsilon();
        const double grow = (eta * double(D) + 8.0 * (D + 1) * eps) * (std::max(radius1_, h.radius1_) + ref1);
        h.tol_ = round_up(double(tol_) + grow + 8.0 * D * eps * h.radius1_);
        return h;
    }

    T volume() const {  // area in 2D; 0 for flat hulls
        if (dim_ < int(D)) return 0;
        double s = 0;
        if constexpr (D == 2) {
            for (std::size_t i = 0; i < vertices_.size(); ++i) {
                const auto a = rel(i), b = rel((i + 1) % vertices_.size());
                s += a[0] * b[1] - a[1] * b[0];
            }
            return T(std::max(0.0, s / 2));
        } else {
            for (const triangle& t : triangles_) {
                const auto a = rel(t[0]), b = rel(t[1]), c = rel(t[2]);
                s += a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
            }
            return T(std::max(0.0, s / 6));  // a sliver's rounding could make it slightly negative
        }
    }
    T surface_area() const {  // perimeter in 2D; flat hulls count both sides
        double s = 0;
        if constexpr (D == 2) {
            if (dim_ < 1) return 0;
            for (std::size_t i = 0; i < vertices_.size(); ++i) {
                const auto a = rel(i), b = rel((i + 1) % vertices_.size());
                s += std::hypot(b[0] - a[0], b[1] - a[1]);
            }
        } else {
            for (const triangle& t : triangles_) {
                const auto a = rel(t[0]), b = rel(t[1]), c = rel(t[2]);
                const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
                const double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2], z = u[0] * w[1] - u[1] * w[0];
                s += std::sqrt(x * x + y * y + z * z) / 2;
            }
        }
        return T(s);
    }

    // Index of a vertex maximising dir . (v - reference()), up to the rounding of that dot
    // product. Hill climbing on the vertex graph from `start`: on a convex polytope a vertex
    // that is not optimal has a strictly better neighbour, so a local maximum is global.
    // Rounding can make a better neighbour look equal or slightly worse (near-duplicate
    // vertices form such "plateaus"), so at a local maximum the climb also explores every
    // vertex connected to it within delta (twice the dot's error bound) of its value and
    // resumes from any strictly better one; then the returned value is within the error bound
    // of the true maximum (a strictly increasing path from the returned vertex to the optimum
    // would have stayed inside the explored plateau). Linear scan for small hulls.
    index_type support_index(const std::array<double, D>& dir, index_type start = 0) const {
        const std::size_t n = vertices_.size();
        if (n <= 32 || adj_start_.empty()) {
            index_type best = 0;
            double bv = -std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i < n; ++i) {
                const double x = dot_rel(dir, static_cast<index_type>(i));
                if (x > bv) bv = x, best = static_cast<index_type>(i);
            }
            return best;
        }
        double dmax = 0;
        for (double x : dir) dmax = std::max(dmax, std::abs(x));
        const double delta = 8 * std::numeric_limits<double>::epsilon() * dmax * radius1_;
        index_type cur = start < n ? start : 0;
        double cv = dot_rel(dir, cur);
        small_set plateau;
        small_stack stack;
        for (;;) {
            double second = -std::numeric_limits<double>::infinity();  // best neighbour value
            for (;;) {  // steepest ascent
                index_type next = cur;
                second = -std::numeric_limits<double>::infinity();
                for (index_type k = adj_start_[cur]; k < adj_start_[cur + 1]; ++k) {
                    const double x = dot_rel(dir, adj_[k]);
                    if (x > cv) cv = x, next = adj_[k];
                    else second = std::max(second, x);
                }
                if (next == cur) break;
                cur = next;
            }
            if (second < cv - delta) return cur;  // a strict local maximum: no plateau
            // Explore the plateau around the local maximum.
            plateau.clear();
            stack.clear();
            plateau.insert(cur);
            stack.push_back(cur);
            bool better = false;
            while (!stack.empty() && !better) {
                const index_type u = stack.pop_back();
                for (index_type k = adj_start_[u]; k < adj_start_[u + 1] && !better; ++k) {
                    const index_type w = adj_[k];
                    if (plateau.contains(w)) continue;
                    const double x = dot_rel(dir, w);
                    if (x > cv) {
                        cv = x, cur = w, better = true;
                    } else if (x >= cv - delta) {
                        plateau.insert(w);
                        stack.push_back(w);
                    }
                }
            }
            if (!better) return cur;
        }
    }

private:
    static constexpr index_type none = std::numeric_limits<index_type>::max();

    // Large 3D hulls: vertices in Morton (Z-order) order, triangles grouped by their first
    // vertex and faces numbered in that order, so that the hill climbs over the vertex graph
    // (plane offsets here, supports in overlaps()) touch nearby memory. O(V log V + F).
    static void spatial_order(quickhull_3d_result& r, const std::vector<std::array<double, 3>>& q) {
        std::array<double, 3> lo = q[r.vertices[0]], hi = lo;
        for (auto v : r.vertices)
            for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], q[v][k]), hi[k] = std::max(hi[k], q[v][k]);
        auto spread = [](std::uint64_t x) {  // 21 bits -> every third bit
            x &= 0x1fffff;
            x = (x | x << 32) & 0x1f00000000ffffULL;
            x = (x | x << 16) & 0x1f0000ff0000ffULL;
            x = (x | x << 8) & 0x100f00f00f00f00fULL;
            x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
            x = (x | x << 2) & 0x1249249249249249ULL;
            return x;
        };
        std::vector<std::pair<std::uint64_t, index_type>> key(r.vertices.size());
        for (std::size_t i = 0; i < key.size(); ++i) {
            std::uint64_t code = 0;
            for (int k = 0; k < 3; ++k) {
                const double ext = hi[k] - lo[k];
                const double f = ext > 0 ? (q[r.vertices[i]][k] - lo[k]) / ext : 0.0;
                code |= spread(static_cast<std::uint64_t>(std::clamp(f, 0.0, 1.0) * 2097151.0)) << k;
            }
            key[i] = {code, r.vertices[i]};
        }
        std::sort(key.begin(), key.end());
        std::vector<index_type> rank(q.size(), none);
        for (std::size_t i = 0; i < key.size(); ++i) r.vertices[i] = key[i].second, rank[key[i].second] = static_cast<index_type>(i);
        // Counting sort of the triangles by the rank of their first vertex.
        std::vector<index_type> start(key.size() + 1, 0);
        for (const auto& t : r.triangles) ++start[rank[t[0]] + 1];
        for (std::size_t i = 0; i < key.size(); ++i) start[i + 1] += start[i];
        std::vector<std::array<std::uint32_t, 3>> tris(r.triangles.size());
        std::vector<std::uint32_t> faces(r.faces.size());
        for (std::size_t t = 0; t < r.triangles.size(); ++t) {
            const index_type at = start[rank[r.triangles[t][0]]]++;
            tris[at] = r.triangles[t];
            faces[at] = r.faces[t];
        }
        std::vector<std::uint32_t> id(r.face_count, none);
        std::uint32_t next = 0;
        for (auto& f : faces) {
            if (id[f] == none) id[f] = next++;
            f = id[f];
        }
        r.triangles.swap(tris);
        r.faces.swap(faces);
        r.neighbors.clear();  // no longer matching the triangle order (not used after the fit)
    }

    // Vertex index containers without heap allocation while short (a plateau usually holds a
    // facet's few vertices): a stack, and a set with linear search inline and a hash set
    // beyond (a flat hull's normal plane has every vertex on its plateau).
    static constexpr std::size_t inline_size = 24;
    class small_stack {
    public:
        void clear() { n_ = 0, more_.clear(); }
        bool empty() const { return n_ == 0 && more_.empty(); }
        void push_back(index_type x) {
            if (n_ < inline_size) buf_[n_++] = x;
            else more_.push_back(x);
        }
        index_type pop_back() {
            if (!more_.empty()) {
                const index_type x = more_.back();
                more_.pop_back();
                return x;
            }
            return buf_[--n_];
        }

    private:
        index_type buf_[inline_size];
        std::size_t n_ = 0;
        std::vector<index_type> more_;
    };
    class small_set {
    public:
        void clear() { n_ = 0, more_.clear(); }
        void insert(index_type x) {
            if (n_ < inline_size) buf_[n_++] = x;
            else more_.insert(x);
        }
        bool contains(index_type x) const {
            for (std::size_t i = 0; i < n_; ++i)
                if (buf_[i] == x) return true;
            return !more_.empty() && more_.count(x) != 0;
        }

    private:
        index_type buf_[inline_size];
        std::size_t n_ = 0;
        std::unordered_set<index_type> more_;
    };

    // Is some facet plane of this hull a separating axis with a gap above `slack`? `delta` is
    // reference() - o.reference(). O(F) supports of o.
    bool face_axis_separates(const convex_hull& o, const std::array<double, D>& delta, double slack) const {
        index_type hint = 0;
        for (const plane& pl : planes_) {
            std::array<double, D> n, m;
            double shift = 0;  // n . (o.reference() - reference())
            for (std::size_t i = 0; i < D; ++i) n[i] = double(pl.normal[i]), m[i] = -n[i], shift -= n[i] * delta[i];
            hint = o.support_index(m, hint);
            const double low = -o.dot_rel(m, hint) + shift;  // min over o of n . (x - reference())
            if (low > double(pl.offset) + slack) return true;
        }
        return false;
    }

    std::vector<point_type> vertices_;
    std::vector<plane> planes_;
    std::vector<triangle> triangles_;
    std::vector<index_type> adj_start_, adj_;  // vertex graph (CSR): polytope edges
    point_type ref_{}, lo_{}, hi_{};
    T tol_ = 0;
    double radius1_ = 0;  // max over vertices of |v - ref_|_1
    int dim_ = -1;

    std::array<double, D> rel(std::size_t i) const {
        std::array<double, D> x;
        for (std::size_t k = 0; k < D; ++k) x[k] = double(vertices_[i][k]) - double(ref_[k]);
        return x;
    }
    double dot_rel(const std::array<double, D>& dir, index_type i) const {
        double s = 0;
        for (std::size_t k = 0; k < D; ++k) s += dir[k] * (double(vertices_[i][k]) - double(ref_[k]));
        return s;
    }
    static T round_up(double x) { return detail_rounding::round_up<T>(x); }

    void update_box_and_radius() {
        lo_ = hi_ = vertices_[0];
        for (const auto& v : vertices_)
            for (std::size_t i = 0; i < D; ++i) lo_[i] = std::min(lo_[i], v[i]), hi_[i] = std::max(hi_[i], v[i]);
        radius1_ = 0;
        for (std::size_t v = 0; v < vertices_.size(); ++v) {
            double s = 0;
            for (double x : rel(v)) s += std::abs(x);
            radius1_ = std::max(radius1_, s);
        }
    }

    // Adds the plane with (unnormalised, double) normal n; the offset is the maximum of the
    // rounded normal over the vertices, found by hill climbing from vertex `start`. Returns
    // false (and adds nothing) if n cannot be normalised.
    //
    // n is first divided by its largest component: the cross products of a hull a few
    // denormals thick have components near 1e-160 and below, whose squares underflow into
    // the denormals and lose their precision, so the length came out wrong and the "unit"
    // normal was longer than 1 (a soak finding: distance_lower_bound then exceeded the true
    // distance and a ball query pruned points on its boundary). Scaled, the largest square is
    // 1 and the length is exact to a few ulps, as distance_lower_bound assumes.
    bool add_plane(std::array<double, D> n, index_type start) {
        double largest = 0;
        for (double x : n) largest = std::max(largest, std::abs(x));
        if (!(largest > 0) || !std::isfinite(largest)) return false;
        for (double& x : n) x /= largest;
        double len = 0;
        for (double x : n) len += x * x;
        len = std::sqrt(len);
        plane pl;
        std::array<double, D> nt;
        for (std::size_t i = 0; i < D; ++i) pl.normal[i] = T(n[i] / len), nt[i] = double(pl.normal[i]);
        const index_type v = support_index(nt, start);
        pl.offset = round_up(dot_rel(nt, v));
        planes_.push_back(pl);
        return true;
    }

    void build_adjacency() {
        const std::size_t n = vertices_.size();
        adj_start_.assign(n + 1, 0);
        adj_.clear();
        auto add_ring = [&] {  // polygon: each vertex adjacent to its two ring neighbours
            for (std::size_t i = 0; i <= n; ++i) adj_start_[i] = static_cast<index_type>(2 * i);
            adj_.resize(2 * n);
            for (std::size_t i = 0; i < n; ++i) {
                adj_[2 * i] = static_cast<index_type>((i + 1) % n);
                adj_[2 * i + 1] = static_cast<index_type>((i + n - 1) % n);
            }
        };
        if (dim_ == 2) {
            add_ring();
        } else if (dim_ == 3) {
            // Every edge u -> v of a triangle, once per direction over the closed surface.
            for (const triangle& t : triangles_)
                for (int k = 0; k < 3; ++k) ++adj_start_[t[k] + 1];
            for (std::size_t i = 0; i < n; ++i) adj_start_[i + 1] += adj_start_[i];
            adj_.resize(adj_start_[n]);
            std::vector<index_type> fill(adj_start_.begin(), adj_start_.end() - 1);
            for (const triangle& t : triangles_)
                for (int k = 0; k < 3; ++k) adj_[fill[t[k]]++] = t[(k + 1) % 3];
        } else {
            adj_start_.clear();  // <= 2 vertices: linear scans
        }
    }

    void finish(const std::vector<std::uint32_t>& faces, std::size_t face_count) {
        update_box_and_radius();
        for (std::size_t i = 0; i < D; ++i) ref_[i] = lo_[i] + (hi_[i] - lo_[i]) / 2;
        update_box_and_radius();  // radius relative to the final reference point
        tol_ = round_up(8.0 * D * double(std::numeric_limits<T>::epsilon()) * radius1_);
        build_adjacency();
        planes_.clear();
        bool complete = true;
        auto axis = [](std::size_t k, double s) {
            std::array<double, D> e{};
            e[k] = s;
            return e;
        };
        if (dim_ == 0) {
            for (std::size_t k = 0; k < D; ++k) add_plane(axis(k, 1), 0), add_plane(axis(k, -1), 0);
        } else if (dim_ == 1) {
            const auto a = rel(0), b = rel(1);
            std::array<double, D> u;
            for (std::size_t i = 0; i < D; ++i) u[i] = b[i] - a[i];
            std::array<std::array<double, D>, D> frame{};  // u and D-1 perpendiculars
            frame[0] = u;
            if constexpr (D == 2) {
                frame[1] = {-u[1], u[0]};
            } else {
                std::size_t k = 0;  // the axis least aligned with u
                for (std::size_t i = 1; i < 3; ++i)
                    if (std::abs(u[i]) < std::abs(u[k])) k = i;
                const auto e = axis(k, 1);
                frame[1] = cross(u, e);
                frame[2] = cross(u, frame[1]);
            }
            for (const auto& f : frame) {
                std::array<double, D> m;
                for (std::size_t i = 0; i < D; ++i) m[i] = -f[i];
                complete = add_plane(f, 0) && complete;
                complete = add_plane(m, 0) && complete;
            }
        } else if (dim_ == 2) {
            const std::size_t k = vertices_.size();
            if constexpr (D == 2) {
                for (std::size_t i = 0; i < k; ++i) {
                    const auto a = rel(i), b = rel((i + 1) % k);
                    complete = add_plane({b[1] - a[1], a[0] - b[0]}, static_cast<index_type>(i)) && complete;
                }
            } else {
                // Polygon normal: the sum of the fan's cross products (the first half of
                // triangles_ faces this way, the vertices run counter-clockwise about it).
                std::array<double, 3> m{};
                for (std::size_t t = 0; t < triangles_.size() / 2; ++t) {
                    const auto c = triangle_cross(triangles_[t]);
                    for (int i = 0; i < 3; ++i) m[std::size_t(i)] += c[std::size_t(i)];
                }
                complete = add_plane(m, 0) && complete;
                complete = add_plane({-m[0], -m[1], -m[2]}, 0) && complete;
                for (std::size_t i = 0; i < k; ++i) {
                    const auto a = rel(i), b = rel((i + 1) % k);
                    const std::array<double, 3> e = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
                    complete = add_plane(cross(e, m), static_cast<index_type>(i)) && complete;
                }
            }
        } else if constexpr (D == 3) {
            complete = add_facet_planes(faces, face_count);
        }
        // A normal that could not be computed leaves its half-space out; the box planes then
        // keep the intersection bounded (never observed; kept for the guarantee).
        if (!complete)
            for (std::size_t k = 0; k < D; ++k) add_plane(axis(k, 1), 0), add_plane(axis(k, -1), 0);
    }

    static std::array<double, 3> cross(const std::array<double, 3>& u, const std::array<double, 3>& w) {
        return {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    }
    // (b - a) x (c - a) evaluated from the two shortest edges: the cross product's absolute
    // rounding error scales with the product of the edge lengths used, its value does not.
    std::array<double, 3> triangle_cross(const triangle& t) const {
        const std::array<double, 3> p[3] = {rel3(t[0]), rel3(t[1]), rel3(t[2])};
        std::size_t apex = 0;  // the vertex opposite the longest edge
        double longest = -1;
        for (std::size_t k = 0; k < 3; ++k) {
            const auto& x = p[(k + 1) % 3];
            const auto& y = p[(k + 2) % 3];
            const double l = (x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) + (x[2] - y[2]) * (x[2] - y[2]);
            if (l > longest) longest = l, apex = k;
        }
        const auto& a = p[apex];
        const auto& b = p[(apex + 1) % 3];
        const auto& c = p[(apex + 2) % 3];
        return cross({b[0] - a[0], b[1] - a[1], b[2] - a[2]}, {c[0] - a[0], c[1] - a[1], c[2] - a[2]});
    }
    std::array<double, 3> rel3(index_type i) const {
        const auto x = rel(i);
        if constexpr (D == 3) return {x[0], x[1], x[2]};
        else return {x[0], x[1], 0.0};
    }

    // 3D polytope: one plane per face (maximal group of exactly coplanar adjacent triangles,
    // from quickhull_3d); the face's normal is the sum of its triangles' cross products.
    bool add_facet_planes(const std::vector<std::uint32_t>& faces, std::size_t face_count) {
        std::vector<std::array<double, 3>> sum(face_count, std::array<double, 3>{0, 0, 0});
        std::vector<index_type> start(face_count, none);
        for (std::size_t t = 0; t < triangles_.size(); ++t) {
            const auto c = triangle_cross(triangles_[t]);
            auto& s = sum[faces[t]];
            for (int i = 0; i < 3; ++i) s[std::size_t(i)] += c[std::size_t(i)];
            if (start[faces[t]] == none) start[faces[t]] = triangles_[t][0];
        }
        bool complete = true;
        for (std::size_t f = 0; f < face_count; ++f) {
            std::array<double, D> n;
            for (std::size_t i = 0; i < D; ++i) n[i] = sum[f][i];
            complete = add_plane(n, start[f]) && complete;
        }
        return complete;
    }
};

static_assert(bounding_volume<convex_hull<double, 3>>);
static_assert(bounding_volume<convex_hull<float, 2>>);

}  // namespace spatial
