#pragma once
// spatial::quickhull_3d — the convex hull of a 3D point set by Quickhull (Barber, Dobkin &
// Huhdanpaa 1996, "The Quickhull algorithm for convex hulls", ACM TOMS 22(4)), the engine
// of convex_hull<T, 3>.
//
// Algorithm. An initial tetrahedron from extreme points; every point is put in the conflict
// ("outside") list of one facet it lies strictly above, points above none are discarded.
// Repeatedly: take a facet with a non-empty list, its farthest point is the eye; the facets
// the eye sees are found by a depth-first search over facet adjacency from that facet, which
// also yields the horizon (the boundary of the visible region) in cyclic order; the visible
// facets are replaced by a cone of new triangles from the eye to the horizon edges, and the
// conflict points of the removed facets are re-assigned to the first new facet they lie
// above (or discarded). Conflict entries carry their coordinates so that the re-assignment
// streams through memory; lists and facet slots are recycled.
//
// Complexity: O(n log r) expected for r output vertices under Barber et al.'s balance
// assumptions (O(n log n) when every point is a vertex, e.g. points on a sphere); O(n r)
// worst case. Memory O(n) (about 100 bytes per live facet plus 32 per conflict entry).
//
// Robustness: every above/below decision is an orientation test with an exact sign
// (predicates.hpp: Shewchuk's error-bounded floating-point filter, exact expansion arithmetic
// on the rare uncertain cases). So the hull maintained is always the exact convex hull of the
// points inserted so far, the visible region is always a topological disc, and the output is
// a closed, consistently oriented triangulated sphere (every edge in exactly two triangles,
// V - E + F = 2) whose vertices are exactly the extreme input points: points on a facet or an
// edge (coplanar / collinear) are not vertices, and planar faces come out triangulated
// (`faces` groups their triangles). Quickhull alone can leave a non-extreme point as a
// vertex inside a face or an edge when the input is exactly coplanar there (an early
// "farthest" choice among ties); a final pass counts the face-boundary edges at each vertex
// (fewer than three: not extreme) and, if any such vertex exists, recomputes the hull of the
// extreme vertices alone, whose vertices are then exactly those points (every point inserted
// is extreme, and an extreme point is never removed).
// This replaces the thick-plane epsilon tests of qhull (which need facet merging to keep the
// topology valid) by exactness; the tolerance lives only in the query side (convex_hull's
// contains()). Guarantee assumes finite coordinates within about 1e-90 .. 1e90 in magnitude
// (products must neither overflow nor underflow).
//
// Degenerate input (decided exactly): no points -> dimension -1; all points equal ->
// dimension 0 (one vertex); collinear -> dimension 1 (the two extreme points); coplanar ->
// dimension 2: the polygon's vertices in counter-clockwise order (Andrew's monotone chain,
// exact, in the coordinate plane that keeps the polygon non-degenerate) and a closed "double
// covered" triangulation (a fan from vertex 0 on one side, from vertex 1 on the other:
// 2(k - 2) triangles, every edge in exactly two, V - E + F = 2).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "spatial/bv/hull_2d.hpp"
#include "spatial/bv/predicates.hpp"
#include "spatial/core/free_list.hpp"

namespace spatial {

struct quickhull_3d_result {
    int dimension = -1;  // affine dimension of the input: -1 (empty) .. 3
    // Input indices of the hull's vertices. Dimension 2: the polygon in counter-clockwise
    // order seen from the side that `triangles`' first half faces. Dimension 3: any order.
    std::vector<std::uint32_t> vertices;
    // Input-index triangles, counter-clockwise seen from outside (outward normals). Empty
    // for dimension < 2.
    std::vector<std::array<std::uint32_t, 3>> triangles;
    // Dimension 3 only: neighbors[t][k] is the triangle across edge (v[k], v[k + 1]) of t;
    // faces[t] the face (maximal group of exactly coplanar adjacent triangles) of t, in
    // [0, face_count).
    std::vector<std::array<std::uint32_t, 3>> neighbors;
    std::vector<std::uint32_t> faces;
    std::size_t face_count = 0;
};

namespace detail {

class quickhull_3d_builder {
public:
    using u32 = std::uint32_t;
    using vec3 = std::array<double, 3>;

    explicit quickhull_3d_builder(std::span<const vec3> pts) : pts_(pts) {}

    quickhull_3d_result run() {
        quickhull_3d_result out;
        if (pts_.empty()) return out;
        if (pts_.size() >= std::size_t(none)) throw std::length_error("quickhull_3d: too many points (indices are 32-bit)");
        u32 a, b, c, d;
        out.dimension = initial_simplex(a, b, c, d);
        if (out.dimension == 0) {
            out.vertices = {a};
            return out;
        }
        if (out.dimension == 1) {
            out.vertices = {a, b};
            return out;
        }
        if (out.dimension == 2) {
            flat_hull(a, b, c, out);
            return out;
        }
        build_tetrahedron(a, b, c, d);
        while (!pending_.empty()) {
            const u32 f = pending_.back();
            pending_.pop_back();
            if (!facets_[f].alive || facets_[f].list == none) continue;
            const conflict eye = lists_[facets_[f].list][facets_[f].far];
            add_point(f, eye);
        }
        std::vector<char> used(pts_.size(), 0);
        std::vector<u32> slot(facets_.size(), none);
        for (std::size_t i = 0; i < facets_.size(); ++i) {
            const facet& f = facets_[i];
            if (!f.alive) continue;
            slot[i] = static_cast<u32>(out.triangles.size());
            out.triangles.push_back({f.v[0], f.v[1], f.v[2]});
            for (u32 v : f.v) used[v] = 1;
        }
        for (const facet& f : facets_)
            if (f.alive) out.neighbors.push_back({slot[f.nb[0]], slot[f.nb[1]], slot[f.nb[2]]});
        for (std::size_t i = 0; i < used.size(); ++i)
            if (used[i]) out.vertices.push_back(static_cast<u32>(i));
        facets_ = {};
        lists_ = {};
        std::vector<u32> extreme;
        if (classify(out, extreme) || !allow_rebuild) return out;
        // Some vertices are not extreme (they lie inside a face or an edge of the final
        // hull: with exactly coplanar input a point chosen early as "farthest" can end up
        // there, and Quickhull only removes vertices that end up strictly inside). The hull
        // of the extreme vertices alone has exactly them as vertices (every point inserted
        // is then extreme, and an extreme point is never removed), so one more pass on
        // those few points gives the exact answer.
        std::vector<vec3> sub(extreme.size());
        for (std::size_t i = 0; i < extreme.size(); ++i) sub[i] = pts_[extreme[i]];
        quickhull_3d_builder again(sub);
        again.allow_rebuild = false;
        quickhull_3d_result r = again.run();
        for (u32& v : r.vertices) v = extreme[v];
        for (auto& t : r.triangles)
            for (u32& v : t) v = extreme[v];
        return r;
    }

private:
    static constexpr u32 none = std::numeric_limits<u32>::max();

    struct conflict {
        double x, y, z;
        u32 index;
    };
    struct facet {
        u32 v[3];    // counter-clockwise seen from outside
        u32 nb[3];   // nb[k]: the facet across edge (v[k], v[k+1])
        double n[3]; // (v0 - v2) x (v1 - v2) in floating point (outward, not normalised)
        double perm[3]; // filter bound per unit of |p_k - v2_k| (orient_3d_filter * that row of the permanent)
        double far_det;
        u32 list;    // conflict list (index into lists_) or none
        u32 far;     // position of the farthest conflict point in the list
        u32 stamp;   // == stamp_ when visited by the current horizon search
        bool alive;
        bool visible;
    };
    struct horizon_edge {
        u32 from, to, outer;
    };
    struct dfs_frame {
        u32 f;
        int i, entry;
    };

    std::span<const vec3> pts_;
    std::vector<facet> facets_;
    std::vector<u32> free_facets_;
    std::vector<std::vector<conflict>> lists_;
    std::vector<u32> free_lists_;
    std::vector<u32> pending_;  // facets that received conflict points (a stack)
    u32 stamp_ = 0;
    std::vector<u32> visible_, new_facets_, next_edge_;
    std::vector<horizon_edge> horizon_, ordered_;
    std::vector<dfs_frame> dfs_;
    std::vector<conflict> moving_;
    bool allow_rebuild = true;

    // Groups the triangles into faces (maximal sets of exactly coplanar adjacent triangles,
    // union-find) and counts, per vertex, the incident edges between different faces: a
    // vertex on at most two of them lies inside a face or an edge, so it is not extreme
    // (at a true vertex at least three faces meet). Returns true if every vertex is extreme;
    // otherwise `extreme` receives the extreme ones.
    bool classify(quickhull_3d_result& out, std::vector<u32>& extreme) const {
        const std::size_t nt = out.triangles.size();
        std::vector<u32> parent(nt);
        for (std::size_t t = 0; t < nt; ++t) parent[t] = static_cast<u32>(t);
        auto find = [&](u32 x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        std::vector<std::uint8_t> ridges(pts_.size(), 0);  // saturating count of face-boundary edges
        for (std::size_t t = 0; t < nt; ++t)
            for (int k = 0; k < 3; ++k) {
                const u32 u = out.neighbors[t][k];
                if (u <= t) continue;
                const auto& a = out.triangles[t];
                const auto& b = out.triangles[u];
                const u32 e0 = a[k], e1 = a[(k + 1) % 3];
                u32 opp = b[0];
                for (u32 v : b)
                    if (v != e0 && v != e1) opp = v;
                if (predicates::orient_3d(pts_[a[0]].data(), pts_[a[1]].data(), pts_[a[2]].data(), pts_[opp].data()) == 0) {
                    parent[find(u)] = find(static_cast<u32>(t));
                } else {
                    if (ridges[e0] < 3) ++ridges[e0];
                    if (ridges[e1] < 3) ++ridges[e1];
                }
            }
        out.faces.resize(nt);
        std::vector<u32> id(nt, none);
        out.face_count = 0;
        for (std::size_t t = 0; t < nt; ++t) {
            const u32 r = find(static_cast<u32>(t));
            if (id[r] == none) id[r] = static_cast<u32>(out.face_count++);
            out.faces[t] = id[r];
        }
        bool all = true;
        for (u32 v : out.vertices) all = all && ridges[v] >= 3;
        if (all) return true;
        extreme.clear();
        for (u32 v : out.vertices)
            if (ridges[v] >= 3) extreme.push_back(v);
        return false;
    }

    // Sign of the orientation of p with respect to facet f (> 0: strictly above/outside);
    // `det` receives the floating-point value, proportional to the distance.
    int side(const facet& f, const conflict& p, double& det) const {
        const vec3& c = pts_[f.v[2]];  // the base point: the eye for the newest facets (cached)
        const double px = p.x - c[0], py = p.y - c[1], pz = p.z - c[2];
        det = f.n[0] * px + f.n[1] * py + f.n[2] * pz;
        const double bound = f.perm[0] * std::abs(px) + f.perm[1] * std::abs(py) + f.perm[2] * std::abs(pz);
        if (det > bound) return 1;
        if (det < -bound) return -1;
        const double q[3] = {p.x, p.y, p.z};
        return predicates::orient_3d_exact(pts_[f.v[0]].data(), pts_[f.v[1]].data(), c.data(), q);
    }

    u32 make_facet(u32 a, u32 b, u32 c) {
        const u32 id = detail::reuse_or_grow(free_facets_, [this] {
            facets_.emplace_back();
            return static_cast<u32>(facets_.size() - 1);
        });
        facet& f = facets_[id];
        f.v[0] = a, f.v[1] = b, f.v[2] = c;
        f.nb[0] = f.nb[1] = f.nb[2] = none;
        // n = (a - c) x (b - c) = (b - a) x (c - a), with c as the base point.
        const vec3 &pa = pts_[a], &pb = pts_[b], &pc = pts_[c];
        const double u[3] = {pa[0] - pc[0], pa[1] - pc[1], pa[2] - pc[2]};
        const double w[3] = {pb[0] - pc[0], pb[1] - pc[1], pb[2] - pc[2]};
        for (int k = 0; k < 3; ++k) {
            const int i = (k + 1) % 3, j = (k + 2) % 3;
            const double l = u[i] * w[j], r = u[j] * w[i];
            f.n[k] = l - r;
            f.perm[k] = predicates::orient_3d_filter * (std::abs(l) + std::abs(r));
        }
        f.far_det = 0;
        f.list = none;
        f.far = 0;
        f.stamp = 0;
        f.alive = true;
        f.visible = false;
        return id;
    }

    void add_conflict(u32 fid, const conflict& c, double det) {
        facet& f = facets_[fid];
        if (f.list == none) {
            f.list = detail::reuse_or_grow(free_lists_, [this] {
                lists_.emplace_back();
                return static_cast<u32>(lists_.size() - 1);
            });
            pending_.push_back(fid);
        }
        auto& l = lists_[f.list];
        if (l.empty() || det > f.far_det) {
            f.far = static_cast<u32>(l.size());
            f.far_det = det;
        }
        l.push_back(c);
    }

    void release_list(facet& f) {
        if (f.list == none) return;
        auto& l = lists_[f.list];
        l.clear();
        // Keep small buffers for reuse; give large ones (early, huge lists) back.
        if (l.capacity() > 4096) std::vector<conflict>().swap(l);
        free_lists_.push_back(f.list);
        f.list = none;
    }

    // Chooses the initial simplex and returns the affine dimension of the whole input,
    // decided with exact predicates (a point found "farthest" in floating point is only a
    // candidate; if it is exactly degenerate every point is checked exactly).
    int initial_simplex(u32& a, u32& b, u32& c, u32& d) {
        const std::size_t n = pts_.size();
        u32 ext[6] = {0, 0, 0, 0, 0, 0};
        for (std::size_t i = 1; i < n; ++i)
            for (int k = 0; k < 3; ++k) {
                if (pts_[i][k] < pts_[ext[2 * k]][k]) ext[2 * k] = static_cast<u32>(i);
                if (pts_[i][k] > pts_[ext[2 * k + 1]][k]) ext[2 * k + 1] = static_cast<u32>(i);
            }
        double best = -1;
        a = b = c = d = 0;
        for (int i = 0; i < 6; ++i)
            for (int j = i + 1; j < 6; ++j) {
                double s = 0;
                for (int k = 0; k < 3; ++k) {
                    const double t = pts_[ext[i]][k] - pts_[ext[j]][k];
                    s += t * t;
                }
                if (s > best) best = s, a = ext[i], b = ext[j];
            }
        if (pts_[a] == pts_[b]) return 0;  // the bounding box is a point: all points are equal
        // c: farthest from line ab.
        const vec3 &pa = pts_[a], &pb = pts_[b];
        const double ab[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        best = -1;
        for (std::size_t i = 0; i < n; ++i) {
            const double v[3] = {pts_[i][0] - pa[0], pts_[i][1] - pa[1], pts_[i][2] - pa[2]};
            const double x = v[1] * ab[2] - v[2] * ab[1], y = v[2] * ab[0] - v[0] * ab[2], z = v[0] * ab[1] - v[1] * ab[0];
            const double s = x * x + y * y + z * z;
            if (s > best) best = s, c = static_cast<u32>(i);
        }
        if (predicates::collinear_3d(pa.data(), pb.data(), pts_[c].data())) {
            bool found = false;
            for (std::size_t i = 0; i < n && !found; ++i)
                if (!predicates::collinear_3d(pa.data(), pb.data(), pts_[i].data())) c = static_cast<u32>(i), found = true;
            if (!found) return 1;
        }
        // d: farthest from plane abc.
        const vec3& pc = pts_[c];
        const double ac[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
        const double nrm[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
        best = -1;
        for (std::size_t i = 0; i < n; ++i) {
            const double s = std::abs(nrm[0] * (pts_[i][0] - pa[0]) + nrm[1] * (pts_[i][1] - pa[1]) + nrm[2] * (pts_[i][2] - pa[2]));
            if (s > best) best = s, d = static_cast<u32>(i);
        }
        if (predicates::orient_3d(pa.data(), pb.data(), pc.data(), pts_[d].data()) == 0) {
            bool found = false;
            for (std::size_t i = 0; i < n && !found; ++i)
                if (predicates::orient_3d(pa.data(), pb.data(), pc.data(), pts_[i].data()) != 0) d = static_cast<u32>(i), found = true;
            if (!found) return 2;
        }
        return 3;
    }

    // Coplanar input: the exact 2D hull in a coordinate plane onto which the input plane
    // projects bijectively (the projection of a, b, c is not collinear, decided exactly).
    void flat_hull(u32 a, u32 b, u32 c, quickhull_3d_result& out) const {
        const vec3 &pa = pts_[a], &pb = pts_[b], &pc = pts_[c];
        const double u[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        const double w[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
        const double nrm[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        int axes[3] = {0, 1, 2};
        std::sort(axes, axes + 3, [&](int x, int y) { return std::abs(nrm[x]) > std::abs(nrm[y]); });
        int drop = -1;
        for (int k : axes) {
            const int i = (k + 1) % 3, j = (k + 2) % 3;
            const double qa[2] = {pa[i], pa[j]}, qb[2] = {pb[i], pb[j]}, qc[2] = {pc[i], pc[j]};
            if (predicates::orient_2d(qa, qb, qc) != 0) {
                drop = k;
                break;
            }
        }
        if (drop < 0) throw std::logic_error("quickhull_3d: flat hull without a non-degenerate projection");
        const int i = (drop + 1) % 3, j = (drop + 2) % 3;
        const auto poly = hull_2d_indices(pts_.size(), [&](std::size_t q) { return std::array<double, 2>{pts_[q][i], pts_[q][j]}; });
        for (std::size_t q : poly) out.vertices.push_back(static_cast<u32>(q));
        const std::size_t k = poly.size();
        for (std::size_t m = 1; m + 1 < k; ++m)  // the side facing +e_drop
            out.triangles.push_back({out.vertices[0], out.vertices[m], out.vertices[m + 1]});
        // The other side, fanned from vertex 1 so that no diagonal is shared with the first
        // side (otherwise a diagonal would lie in four triangles).
        for (std::size_t m = 2; m < k; ++m)
            out.triangles.push_back({out.vertices[1], out.vertices[(m + 1) % k], out.vertices[m]});
    }

    void link(u32 f, u32 g) {  // set the mutual neighbour pointers of two facets sharing an edge
        facet &F = facets_[f], &G = facets_[g];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (F.v[i] == G.v[(j + 1) % 3] && F.v[(i + 1) % 3] == G.v[j]) F.nb[i] = g, G.nb[j] = f;
    }

    void build_tetrahedron(u32 a, u32 b, u32 c, u32 d) {
        // Orient so that d is below plane (a, b, c); then these four faces point outward.
        if (predicates::orient_3d(pts_[a].data(), pts_[b].data(), pts_[c].data(), pts_[d].data()) > 0) std::swap(b, c);
        const u32 f[4] = {make_facet(a, b, c), make_facet(b, a, d), make_facet(c, b, d), make_facet(a, c, d)};
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) link(f[i], f[j]);
        // Akl & Toussaint style early discard comes for free: a point inside the
        // tetrahedron is above none of its facets and is dropped here.
        for (std::size_t i = 0; i < pts_.size(); ++i) {
            const conflict p{pts_[i][0], pts_[i][1], pts_[i][2], static_cast<u32>(i)};
            for (u32 fid : f) {
                double det;
                if (side(facets_[fid], p, det) > 0) {
                    add_conflict(fid, p, det);
                    break;
                }
            }
        }
    }

    // Puts the horizon edges in cyclic order (to of one == from of the next). The depth-first
    // search already produces them so; this check and repair keep the code independent of
    // that argument. A horizon that is not one simple cycle cannot occur with exact
    // predicates; it would be a bug, reported as such.
    void order_horizon() {
        const std::size_t h = horizon_.size();
        bool ok = true;
        for (std::size_t i = 0; i < h && ok; ++i) ok = horizon_[i].to == horizon_[(i + 1) % h].from;
        if (ok) return;
        if (next_edge_.size() != pts_.size()) next_edge_.assign(pts_.size(), none);
        for (std::size_t i = 0; i < h; ++i) next_edge_[horizon_[i].from] = static_cast<u32>(i);
        ordered_.clear();
        u32 e = 0;
        for (std::size_t s = 0; s < h; ++s) {
            ordered_.push_back(horizon_[e]);
            e = next_edge_[horizon_[e].to];
            if (e == none) break;
        }
        for (const auto& x : horizon_) next_edge_[x.from] = none;
        if (ordered_.size() != h || e != 0) throw std::logic_error("quickhull_3d: the horizon is not a simple cycle");
        horizon_.swap(ordered_);
    }

    void add_point(u32 f0, const conflict& eye) {
        ++stamp_;
        visible_.clear();
        horizon_.clear();
        facets_[f0].stamp = stamp_;
        facets_[f0].visible = true;
        visible_.push_back(f0);
        dfs_.clear();
        dfs_.push_back({f0, 0, 0});
        while (!dfs_.empty()) {
            dfs_frame& top = dfs_.back();
            if (top.i == 3) {
                dfs_.pop_back();
                continue;
            }
            const u32 g = top.f;
            const int e = (top.entry + top.i) % 3;
            ++top.i;
            const u32 h = facets_[g].nb[e];
            facet& H = facets_[h];
            if (H.stamp != stamp_) {
                H.stamp = stamp_;
                double det;
                H.visible = side(H, eye, det) > 0;
                if (H.visible) {
                    visible_.push_back(h);
                    int t = 0;
                    while (H.nb[t] != g || H.v[t] != facets_[g].v[(e + 1) % 3]) ++t;
                    dfs_.push_back({h, 1, t});  // continue around h after the shared edge
                    continue;
                }
            }
            if (!H.visible) horizon_.push_back({facets_[g].v[e], facets_[g].v[(e + 1) % 3], h});
        }
        order_horizon();

        // The cone of new facets over the horizon.
        new_facets_.clear();
        const std::size_t hs = horizon_.size();
        for (const auto& he : horizon_) new_facets_.push_back(make_facet(he.from, he.to, eye.index));
        for (std::size_t i = 0; i < hs; ++i) {
            facet& F = facets_[new_facets_[i]];
            const horizon_edge& he = horizon_[i];
            F.nb[0] = he.outer;
            F.nb[1] = new_facets_[(i + 1) % hs];
            F.nb[2] = new_facets_[(i + hs - 1) % hs];
            facet& O = facets_[he.outer];
            for (int k = 0; k < 3; ++k)
                if (O.v[k] == he.to && O.v[(k + 1) % 3] == he.from) O.nb[k] = new_facets_[i];
        }

        // Re-assign the conflict points of the visible facets.
        std::size_t start = 0;
        for (u32 vf : visible_) {
            facet& V = facets_[vf];
            if (V.list == none) continue;
            moving_.swap(lists_[V.list]);
            for (const conflict& p : moving_) {
                if (p.index == eye.index) continue;
                for (std::size_t s = 0; s < hs; ++s) {
                    const std::size_t j = start + s < hs ? start + s : start + s - hs;
                    double det;
                    if (side(facets_[new_facets_[j]], p, det) > 0) {
                        add_conflict(new_facets_[j], p, det);
                        start = j;  // neighbouring points tend to land on the same facet
                        break;
                    }
                }
            }
            moving_.clear();
            moving_.swap(lists_[facets_[vf].list]);
            release_list(facets_[vf]);
        }
        for (u32 vf : visible_) {
            facet& V = facets_[vf];
            release_list(V);
            V.alive = false;
            free_facets_.push_back(vf);
        }
    }
};

}  // namespace detail

// The convex hull of pts (double triples); see the header comment for the guarantees.
inline quickhull_3d_result quickhull_3d(std::span<const std::array<double, 3>> pts) {
    return detail::quickhull_3d_builder(pts).run();
}

}  // namespace spatial
