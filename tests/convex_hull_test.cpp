// convex_hull<T, D> (issue 3): the fit is the exact hull (vertex set against a brute-force
// Caratheodory reference, volume against brute-force facet enumeration and known polytopes),
// its 3D surface is a closed oriented convex manifold (V - E + F = 2) on random and
// adversarial sets (1-4 points, all equal, collinear, coplanar, grids with many coplanar
// facets, cospherical lattice points, offset 1e8, spread 1e-12, near-duplicates); every input
// point is contained; overlaps() against a brute-force separating-axis reference including
// exactly touching and nearly touching pairs; ray intervals against point sampling; distance
// bounds, merge, transform; the exact orientation predicates against integer arithmetic; the
// generic GJK on spheres.

#include <gtest/gtest.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "spatial/bv/convex_hull.hpp"
#include "spatial/bv/gjk.hpp"
#include "spatial/bv/hull_2d.hpp"
#include "spatial/bv/predicates.hpp"
#include "bv_test_support.hpp"
#include "test_support.hpp"

using namespace spatial;
using spatial_test::unit;

namespace {

template <class P>
std::array<double, 3> as3(const P& p) {
    std::array<double, 3> x{0, 0, 0};
    for (std::size_t i = 0; i < P::dimension; ++i) x[i] = static_cast<double>(p[i]);
    return x;
}
int orient3(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
            const std::array<double, 3>& d) {
    return predicates::orient_3d(a.data(), b.data(), c.data(), d.data());
}
int orient2(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c) {
    return predicates::orient_2d(a.data(), b.data(), c.data());
}
// Orientation in the coordinate plane that drops axis k (cyclic order of the other two).
int orient2_drop(int k, const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double pa[2] = {a[i], a[j]}, pb[2] = {b[i], b[j]}, pc[2] = {c[i], c[j]};
    return predicates::orient_2d(pa, pb, pc);
}

// ---- brute-force references ---------------------------------------------------------------

// Is p in the closed segment [a, b] (a, b, p exactly collinear assumed checked by caller)?
bool between(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& p) {
    for (int i = 0; i < 3; ++i)
        if (p[i] < std::min(a[i], b[i]) || p[i] > std::max(a[i], b[i])) return false;
    return true;
}
bool in_segment(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& p) {
    return predicates::collinear_3d(a.data(), b.data(), p.data()) && between(a, b, p);
}
bool in_triangle(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                 const std::array<double, 3>& p, bool planar_input) {
    if (!planar_input && orient3(a, b, c, p) != 0) return false;
    for (int k = 0; k < 3; ++k) {
        const int s = orient2_drop(k, a, b, c);
        if (s == 0) continue;
        const int s1 = orient2_drop(k, p, b, c), s2 = orient2_drop(k, a, p, c), s3 = orient2_drop(k, a, b, p);
        return (s1 == 0 || s1 == s) && (s2 == 0 || s2 == s) && (s3 == 0 || s3 == s);
    }
    return false;  // degenerate triangle: covered by segments
}
bool in_tetrahedron(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                    const std::array<double, 3>& d, const std::array<double, 3>& p) {
    const int s = orient3(a, b, c, d);
    if (s == 0) return false;  // degenerate: covered by triangles
    const int t[4] = {orient3(p, b, c, d), orient3(a, p, c, d), orient3(a, b, p, d), orient3(a, b, c, p)};
    for (int x : t)
        if (x != 0 && x != s) return false;
    return true;
}
// Extreme points of a small set by Caratheodory: p (deduplicated) is a vertex of the hull iff
// it lies in no simplex (segment, triangle, tetrahedron) of the other points. O(n^5).
std::set<std::array<double, 3>> brute_extreme_points(std::vector<std::array<double, 3>> p, std::size_t dim) {
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    std::set<std::array<double, 3>> out;
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<std::array<double, 3>> q;
        for (std::size_t j = 0; j < n; ++j)
            if (j != i) q.push_back(p[j]);
        bool inside = false;
        const std::size_t m = q.size();
        for (std::size_t a = 0; a < m && !inside; ++a)
            for (std::size_t b = a + 1; b < m && !inside; ++b) {
                inside = in_segment(q[a], q[b], p[i]);
                for (std::size_t c = b + 1; c < m && !inside; ++c) {
                    inside = in_triangle(q[a], q[b], q[c], p[i], dim == 2);
                    if (dim == 3)
                        for (std::size_t d = c + 1; d < m && !inside; ++d) inside = in_tetrahedron(q[a], q[b], q[c], q[d], p[i]);
                }
            }
        if (!inside) out.insert(p[i]);
    }
    return out;
}

// Volume (area in 2D) of the hull of points in general position by facet enumeration: a
// triple (pair in 2D) is a facet iff all other points lie on one side; sum the cones from an
// interior point. O(n^4) (O(n^3)).
double brute_volume(const std::vector<std::array<double, 3>>& p, std::size_t dim) {
    const std::size_t n = p.size();
    std::array<double, 3> c{0, 0, 0};
    for (const auto& x : p)
        for (int i = 0; i < 3; ++i) c[i] += x[i] / double(n);
    double vol = 0;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            if (dim == 2) {
                int pos = 0, neg = 0;
                for (std::size_t k = 0; k < n; ++k) {
                    if (k == i || k == j) continue;
                    const int s = orient2(p[i], p[j], p[k]);
                    pos += s > 0, neg += s < 0;
                }
                if (pos == 0 || neg == 0) {
                    const double ux = p[i][0] - c[0], uy = p[i][1] - c[1], vx = p[j][0] - c[0], vy = p[j][1] - c[1];
                    vol += std::abs(ux * vy - uy * vx) / 2;
                }
                continue;
            }
            for (std::size_t k = j + 1; k < n; ++k) {
                int pos = 0, neg = 0;
                for (std::size_t l = 0; l < n; ++l) {
                    if (l == i || l == j || l == k) continue;
                    const int s = orient3(p[i], p[j], p[k], p[l]);
                    pos += s > 0, neg += s < 0;
                }
                if (pos == 0 || neg == 0) {
                    double u[3], v[3], w[3];
                    for (int a = 0; a < 3; ++a) u[a] = p[i][a] - c[a], v[a] = p[j][a] - c[a], w[a] = p[k][a] - c[a];
                    vol += std::abs(u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6;
                }
            }
        }
    return vol;
}

// Separating-axis reference for two vertex sets (full-dimensional hulls): the candidate axes
// are a superset of the face normals and edge-edge cross products (every difference of two
// vertices of one set crossed with every difference from the same or the other set; in 2D
// the perpendiculars of all differences). Returns the largest gap found along a unit axis
// (> 0: separated by at least that much; <= 0: they intersect, touching included).
template <std::size_t D>
double sat_gap(const std::vector<std::array<double, 3>>& a, const std::vector<std::array<double, 3>>& b) {
    std::vector<std::array<double, 3>> da, db, axes;
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = i + 1; j < a.size(); ++j) da.push_back({a[j][0] - a[i][0], a[j][1] - a[i][1], a[j][2] - a[i][2]});
    for (std::size_t i = 0; i < b.size(); ++i)
        for (std::size_t j = i + 1; j < b.size(); ++j) db.push_back({b[j][0] - b[i][0], b[j][1] - b[i][1], b[j][2] - b[i][2]});
    auto cross = [](const std::array<double, 3>& u, const std::array<double, 3>& v) {
        return std::array<double, 3>{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    };
    if (D == 2) {
        for (const auto* s : {&da, &db})
            for (const auto& d : *s) axes.push_back({-d[1], d[0], 0});
    } else {
        for (const auto* s : {&da, &db})
            for (std::size_t i = 0; i < s->size(); ++i)
                for (std::size_t j = i + 1; j < s->size(); ++j) axes.push_back(cross((*s)[i], (*s)[j]));
        for (const auto& u : da)
            for (const auto& v : db) axes.push_back(cross(u, v));
    }
    double best = -1e300;
    for (auto n : axes) {
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 1e-300)) continue;
        for (double& x : n) x /= len;
        double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
        for (const auto& x : a) {
            const double s = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
            amin = std::min(amin, s), amax = std::max(amax, s);
        }
        for (const auto& x : b) {
            const double s = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
            bmin = std::min(bmin, s), bmax = std::max(bmax, s);
        }
        best = std::max({best, bmin - amax, amin - bmax});
    }
    return best;
}

// ---- structural validation ------------------------------------------------------------------

// Checks everything a fit must satisfy on any input; returns a description of the first
// failure, or "" if valid. `exact_checks` bounds the O(n F) exact containment checks.
template <class T, std::size_t D>
std::string validate(const convex_hull<T, D>& h, const std::vector<point<T, D>>& pts, std::size_t exact_checks = 2000000) {
    using P = point<T, D>;
    if (pts.empty()) return h.is_empty() ? "" : "non-empty hull of no points";
    if (h.is_empty()) return "empty hull of points";
    if (!std::isfinite(double(h.tolerance())) || h.tolerance() < 0) return "bad tolerance";
    if (!std::isfinite(double(h.volume())) || h.volume() < 0) return "bad volume";
    if (!std::isfinite(double(h.surface_area())) || h.surface_area() < 0) return "bad surface area";
    for (const auto& pl : h.planes()) {
        double n2 = 0;
        for (std::size_t i = 0; i < D; ++i) {
            if (!std::isfinite(double(pl.normal[i]))) return "NaN normal";
            n2 += double(pl.normal[i]) * double(pl.normal[i]);
        }
        if (std::abs(n2 - 1) > 1e-5 || !std::isfinite(double(pl.offset))) return "bad plane";
    }
    for (std::size_t i = 0; i < pts.size(); ++i)
        if (!h.contains(pts[i])) return "input point " + std::to_string(i) + " not contained";
    std::set<std::array<double, 3>> input;
    for (const auto& p : pts) input.insert(as3(p));
    std::vector<std::array<double, 3>> v;
    for (const P& x : h.vertices()) {
        if (!input.count(as3(x))) return "a vertex is not an input point";
        v.push_back(as3(x));
    }
    if (std::set<std::array<double, 3>>(v.begin(), v.end()).size() != v.size()) return "repeated vertex";
    const int dim = h.affine_dimension();
    const std::size_t nv = v.size();
    if (dim == 0 && nv != 1) return "dimension 0 with several vertices";
    if (dim == 1 && nv != 2) return "dimension 1 without two vertices";
    if (dim < int(D) && h.volume() != 0) return "flat hull with non-zero volume";
    if (dim == 0) {
        for (const auto& p : pts)
            if (as3(p) != v[0]) return "dimension 0 but points differ";
    }
    if (dim == 1) {
        for (const auto& p : pts)
            if (!in_segment(v[0], v[1], as3(p))) return "dimension 1 but a point is off the segment";
    }
    if (dim >= 2 && (D == 2 || dim == 2)) {  // a strictly convex polygon, CCW (about its normal in 3D)
        if (nv < 3) return "polygon with < 3 vertices";
        int k = 2;  // a projection axis for 3D
        if (D == 3) {
            for (k = 0; k < 3 && orient2_drop(k, v[0], v[1], v[2]) == 0; ++k) {
            }
            if (k == 3) return "degenerate polygon";
        }
        const int s = orient2_drop(k, v[0], v[1], v[2]);
        for (std::size_t i = 0; i < nv; ++i) {
            const auto &a = v[i], &b = v[(i + 1) % nv], &c = v[(i + 2) % nv];
            if (D == 3 && orient3(v[0], v[1], v[2], c) != 0) return "polygon not planar";
            if (orient2_drop(k, a, b, c) != s) return "polygon not strictly convex";
        }
        std::size_t checks = 0;
        for (const auto& p : pts)
            for (std::size_t i = 0; i < nv && checks < exact_checks; ++i, ++checks) {
                const int o = orient2_drop(k, v[i], v[(i + 1) % nv], as3(p));
                if (o != 0 && o != s) return "point outside a polygon edge";
                if (D == 3 && orient3(v[0], v[1], v[2], as3(p)) != 0) return "point off the polygon's plane";
            }
    }
    if constexpr (D == 3) {
        const auto tris = h.triangles();
        if (dim < 2 && !tris.empty()) return "triangles for a hull of dimension < 2";
        if (dim >= 2) {
            std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
            std::set<std::uint32_t> used;
            for (const auto& t : tris)
                for (int k = 0; k < 3; ++k) {
                    if (t[k] >= nv) return "triangle index out of range";
                    ++edges[{t[k], t[(k + 1) % 3]}];
                    used.insert(t[k]);
                }
            for (const auto& [e, c] : edges) {
                if (c != 1) return "directed edge in two triangles (orientation or manifold broken)";
                if (!edges.count({e.second, e.first})) return "open edge";
            }
            if (used.size() != nv) return "vertex not on the surface";
            const long euler = long(nv) - long(edges.size() / 2) + long(tris.size());
            if (euler != 2) return "Euler characteristic " + std::to_string(euler);
            if (h.facet_count() != tris.size()) return "facet_count mismatch";
        }
        if (dim == 3) {
            // Convex and containing: no vertex and no input point strictly above any triangle.
            std::size_t checks = 0;
            for (const auto& t : tris) {
                if (predicates::collinear_3d(v[t[0]].data(), v[t[1]].data(), v[t[2]].data())) return "degenerate triangle";
                for (const auto& x : v)
                    if (orient3(v[t[0]], v[t[1]], v[t[2]], x) > 0) return "not convex: a vertex above a facet";
            }
            for (std::size_t i = 0; i < pts.size() && checks < exact_checks; ++i)
                for (const auto& t : tris) {
                    ++checks;
                    if (orient3(v[t[0]], v[t[1]], v[t[2]], as3(pts[i])) > 0) return "an input point above a facet (exact)";
                }
        }
    }
    return "";
}

// ---- point sets -----------------------------------------------------------------------------

template <class T, std::size_t D>
struct sets_for {
    using P = point<T, D>;
    using named = std::vector<std::pair<std::string, std::vector<P>>>;
    static P make(std::initializer_list<double> c) {
        P p{};
        std::size_t i = 0;
        for (double x : c)
            if (i < D) p[i++] = static_cast<T>(x);
        return p;
    }
    // The 2^D corners of the unit cube (square), corner m having coordinate d = bit d of m.
    static std::vector<P> unit_cube() {
        std::vector<P> v;
        for (unsigned m = 0; m < (1u << D); ++m) {
            P p;
            for (std::size_t d = 0; d < D; ++d) p[d] = T((m >> d) & 1);
            v.push_back(p);
        }
        return v;
    }
    // A rotation by the angle unit(rng) * turn; in 3D about the axis
    // (u - 0.5, u - 0.5, u - z_minus + z_plus), u = unit(rng) drawn in that order.
    template <class Rng>
    static rigid_transform<T, D> random_rotation(Rng& rng, double z_minus, double z_plus, double turn) {
        if constexpr (D == 2)
            return rigid_transform<T, D>::rotate(T(unit(rng) * turn));
        else
            return rigid_transform<T, D>::rotate(
                P{{T(unit(rng) - 0.5), T(unit(rng) - 0.5), T(unit(rng) - z_minus + z_plus)}}, T(unit(rng) * turn));
    }
    static named build(std::uint64_t seed, std::size_t n_random) {
        std::mt19937_64 rng(seed);
            auto gauss = [&] {
            double s = 0;
            for (int i = 0; i < 12; ++i) s += unit(rng);
            return s - 6;
        };
        named out;
        auto add = [&](const std::string& name, std::size_t n, auto f) {
            std::vector<P> v;
            for (std::size_t i = 0; i < n; ++i) {
                std::array<double, D> x = f(i);
                P p;
                for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(x[d]);
                v.push_back(p);
            }
            out.push_back({name, v});
        };
        auto rnd = [&](double lo, double hi) {
            std::array<double, D> x;
            for (auto& c : x) c = lo + (hi - lo) * unit(rng);
            return x;
        };
        auto on_sphere = [&](double r) {
            std::array<double, D> x;
            double n2 = 0;
            do {
                n2 = 0;
                for (auto& c : x) c = gauss(), n2 += c * c;
            } while (n2 < 1e-6);
            for (auto& c : x) c *= r / std::sqrt(n2);
            return x;
        };
        add("cube", n_random, [&](std::size_t) { return rnd(-1, 1); });
        add("ball", n_random, [&](std::size_t) {
            for (;;) {
                auto x = rnd(-1, 1);
                double n2 = 0;
                for (double c : x) n2 += c * c;
                if (n2 <= 1) return x;
            }
        });
        add("sphere surface", n_random / 2, [&](std::size_t) { return on_sphere(1); });  // > 4096: spatially reordered
        add("gaussian", n_random, [&](std::size_t) {
            std::array<double, D> x;
            for (auto& c : x) c = gauss();
            return x;
        });
        add("one point", 1, [&](std::size_t) { return rnd(-1, 1); });
        add("two points", 2, [&](std::size_t) { return rnd(-1, 1); });
        add("three points", 3, [&](std::size_t) { return rnd(-1, 1); });
        add("four points", 4, [&](std::size_t) { return rnd(-1, 1); });
        add("all equal", 50, [&](std::size_t) {
            std::array<double, D> x;
            x.fill(0.375);
            return x;
        });
        add("collinear (exact)", 60, [&](std::size_t) {  // dyadic t: exact in float too
            const double t = double(rng() % 2048) / 256 - 4;
            std::array<double, D> x;
            for (std::size_t d = 0; d < D; ++d) x[d] = 1 + t * double(1 << d);
            return x;
        });
        add("collinear (rounded)", 60, [&](std::size_t i) {
            std::array<double, D> x;
            for (std::size_t d = 0; d < D; ++d) x[d] = double(i) * 0.01 * double(d + 1);
            return x;
        });
        add("coplanar", 200, [&](std::size_t) {
            auto x = rnd(-1, 1);
            x[D - 1] = 0.5;
            return x;
        });
        add("coplanar tilted", 200, [&](std::size_t) {  // exact plane x + y + z = 1 on a dyadic grid
            std::array<double, D> x;
            for (std::size_t d = 0; d + 1 < D; ++d) x[d] = double(rng() % 64) / 8;
            x[D - 1] = 1;
            for (std::size_t d = 0; d + 1 < D; ++d) x[D - 1] -= x[d];
            return x;
        });
        add("grid 6^D", D == 3 ? 216 : 36, [&](std::size_t i) {
            std::array<double, D> x;
            for (std::size_t d = 0; d < D; ++d) x[d] = double(i / (d == 0 ? 1 : (d == 1 ? 6 : 36)) % 6);
            return x;
        });
        {  // integer points on and inside a sphere of radius^2 = 50 (all on it are extreme)
            std::vector<P> v;
            for (int a = -8; a <= 8; ++a)
                for (int b = -8; b <= 8; ++b)
                    for (int c = (D == 3 ? -8 : 0); c <= (D == 3 ? 8 : 0); ++c)
                        if (a * a + b * b + c * c <= 50) v.push_back(make({double(a), double(b), double(c)}));
            out.push_back({"cospherical lattice", v});
        }
        const double off_spread = sizeof(T) == 4 ? 1024 : 1;
        add("offset 1e8", 300, [&](std::size_t) {
            auto x = rnd(0, off_spread);
            for (auto& c : x) c += 1e8;
            return x;
        });
        add("spread 1e-12", 300, [&](std::size_t) {
            auto x = rnd(0, 1e-12);
            for (auto& c : x) c += 0.5;
            return x;
        });
        {  // near-duplicates: each point and copies moved by one ulp
            std::vector<P> v;
            for (int i = 0; i < 400; ++i) {
                const auto x = rnd(-1, 1);
                P p;
                for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(x[d]);
                v.push_back(p);
                for (std::size_t d = 0; d < D; ++d) {
                    P q = p;
                    q[d] = std::nextafter(q[d], T(2));
                    v.push_back(q);
                    q[d] = std::nextafter(p[d], T(-2));
                    v.push_back(q);
                }
            }
            out.push_back({"near-duplicates", v});
        }
        {  // a box's corners with many points on its faces and edges, and duplicates
            std::vector<P> v;
            for (int i = 0; i < 400; ++i) {
                auto x = rnd(0, 1);
                x[rng() % D] = double(rng() % 2);
                if (i % 3 == 0) x[(rng() % D)] = double(rng() % 2);
                P p;
                for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(x[d]);
                v.push_back(p);
                if (i % 7 == 0) v.push_back(p);
            }
            for (const P& p : unit_cube()) v.push_back(p);
            out.push_back({"box faces", v});
        }
        return out;
    }
};

template <class C>
class hull : public spatial_test::dims_fixture<C> {
protected:
    using hull_t = convex_hull<typename C::scalar, C::dim>;
};

TYPED_TEST_SUITE(hull, spatial_test::dim_types);

TYPED_TEST(hull, valid_closed_convex_and_containing_on_random_and_hard_sets) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    const spatial_test::logged_seed seed(11);
    for (std::uint64_t round = 0; round < 3; ++round)
        for (const auto& [name, pts] : sets_for<T, D>::build(seed + round, 3000)) {
            SCOPED_TRACE(name);
            const H h = H::fit_quickhull(pts);
            const std::string err = validate(h, pts, 400000);
            ASSERT_EQ(err, "") << name << ", round " << round;
        }
}

TYPED_TEST(hull, degenerate_inputs_have_documented_dimension_and_shape) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    auto mk = sets_for<T, D>::make;
    EXPECT_TRUE(H::fit(std::vector<P>{}).is_empty());
    EXPECT_FALSE(H::empty().contains(P{}));
    const std::vector<P> one(7, mk({1.5, -2, 3}));
    const H h0 = H::fit(one);
    EXPECT_EQ(h0.affine_dimension(), 0);
    EXPECT_EQ(h0.vertices().size(), 1u);
    EXPECT_EQ(h0.volume(), T(0));
    EXPECT_EQ(h0.surface_area(), T(0));
    EXPECT_TRUE(h0.contains(one[0]));
    EXPECT_FALSE(h0.contains(mk({1.5, -1.5, 3.5})));
    EXPECT_EQ(h0.facet_count(), 0u);

    std::vector<P> line;
    for (int i = 0; i <= 8; ++i) line.push_back(mk({i * 0.25, i * 0.5, i * 1.0}));
    const H h1 = H::fit(line);
    EXPECT_EQ(h1.affine_dimension(), 1);
    ASSERT_EQ(h1.vertices().size(), 2u);
    std::set<std::array<double, 3>> ends{as3(h1.vertices()[0]), as3(h1.vertices()[1])};
    EXPECT_EQ(ends, (std::set<std::array<double, 3>>{as3(line.front()), as3(line.back())}));
    EXPECT_EQ(h1.volume(), T(0));
    EXPECT_FALSE(h1.contains(mk({0.25, 0.375, 0})));  // off the line
    EXPECT_FALSE(h1.contains(mk({2.25, 4.5, 9})));   // beyond the end
    EXPECT_TRUE(h1.contains(mk({0.375, 0.75, 1.5})));
    EXPECT_EQ(h1.facet_count(), D == 2 ? 1u : 0u);
    const double len = D == 2 ? std::sqrt(4 + 16.0) : std::sqrt(4 + 16.0 + 64);
    EXPECT_NEAR(double(h1.surface_area()), D == 2 ? 2 * len : 0.0, 1e-5);

    // A square (in the plane z = 0.5 in 3D) with interior and edge points.
    std::vector<P> sq;
    for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j) sq.push_back(mk({i * 0.25, j * 0.25, 0.5}));
    const H h2 = H::fit(sq);
    EXPECT_EQ(h2.affine_dimension(), 2);
    EXPECT_EQ(h2.vertices().size(), 4u);
    if constexpr (D == 2) {
        EXPECT_NEAR(double(h2.volume()), 1.0, 1e-6);
        EXPECT_NEAR(double(h2.surface_area()), 4.0, 1e-6);
        EXPECT_EQ(h2.facet_count(), 4u);
    } else {
        EXPECT_EQ(h2.volume(), T(0));
        EXPECT_NEAR(double(h2.surface_area()), 2.0, 1e-6);  // both sides
        EXPECT_EQ(h2.facet_count(), 4u);                   // 2 (k - 2)
        EXPECT_FALSE(h2.contains(mk({0.5, 0.5, 0.5001})));
        EXPECT_TRUE(h2.contains(mk({0.5, 0.5, 0.5})));
        T t0, t1;  // a ray through the flat square hits it in a (tiny) interval
        ASSERT_TRUE(h2.ray_interval(mk({0.5, 0.5, 2}), mk({0, -0.0, -1}), t0, t1));
        EXPECT_NEAR(double(t0), 1.5, 1e-5);
        EXPECT_NEAR(double(t1), 1.5, 1e-5);
    }
}

// The vertex set equals the brute-force set of extreme points on small sets, including
// degenerate ones (many coplanar / collinear / duplicate points on a small integer grid).
TYPED_TEST(hull, vertices_are_exactly_the_extreme_points_small_sets) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    spatial_test::seeded_rng rng(12);
    for (int trial = 0; trial < 300; ++trial) {
        const std::size_t n = 1 + rng() % (D == 3 ? 14 : 20);
        const int grid = trial % 3 == 0 ? 3 : (trial % 3 == 1 ? 6 : 1000);
        std::vector<P> pts(n);
        for (auto& p : pts)
            for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(double(rng() % unsigned(grid)) / grid);
        if (trial % 5 == 0)  // force coplanar / collinear inputs
            for (auto& p : pts) p[D - 1] = T(0.5);
        if (trial % 10 == 0 && D == 3)
            for (auto& p : pts) p[1] = p[0];
        const H h = H::fit(pts);
        ASSERT_EQ(validate(h, pts), "") << "trial " << trial;
        std::vector<std::array<double, 3>> raw;
        for (const auto& p : pts) raw.push_back(as3(p));
        const auto want = brute_extreme_points(raw, D);
        std::set<std::array<double, 3>> got;
        for (const auto& v : h.vertices()) got.insert(as3(v));
        ASSERT_EQ(got, want) << "trial " << trial << " n " << n;
    }
}

TYPED_TEST(hull, volume_matches_brute_force_facets_and_known_polytopes) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    spatial_test::seeded_rng rng(13);
    for (int trial = 0; trial < 40; ++trial) {  // general position: facets are unique triples
        const std::size_t n = 4 + rng() % 22;
        std::vector<P> pts(n);
        std::vector<std::array<double, 3>> raw;
        for (auto& p : pts) {
            for (std::size_t d = 0; d < D; ++d) p[d] = static_cast<T>(unit(rng) * 2 - 1);
            raw.push_back(as3(p));
        }
        const H h = H::fit(pts);
        const double want = brute_volume(raw, D);
        const double rel = sizeof(T) == 4 ? 1e-6 : 1e-9;  // the result is rounded to T
        ASSERT_NEAR(double(h.volume()), want, rel * want + 1e-12) << "trial " << trial;
    }
    // Known polytopes: a rotated, offset unit cube (square) with interior points: volume 1;
    // the cross-polytope (octahedron / diamond) of radius 1: 4/3 in 3D, 2 in 2D.
    for (int trial = 0; trial < 10; ++trial) {
        rigid_transform<T, D> xf = sets_for<T, D>::random_rotation(rng, 0, 0.1, 6);
        for (std::size_t d = 0; d < D; ++d) xf.translation[d] = T(unit(rng) * 10);
        std::vector<P> pts;
        for (const P& p : sets_for<T, D>::unit_cube()) pts.push_back(xf.apply(p));
        for (int i = 0; i < 100; ++i) {
            P p;
            for (std::size_t d = 0; d < D; ++d) p[d] = T(0.05 + 0.9 * unit(rng));
            pts.push_back(xf.apply(p));
        }
        const H h = H::fit(pts);
        EXPECT_EQ(h.vertices().size(), std::size_t(1) << D) << "trial " << trial;
        const double tol = sizeof(T) == 4 ? 2e-5 : 1e-12;
        EXPECT_NEAR(double(h.volume()), 1.0, tol);
        EXPECT_NEAR(double(h.surface_area()), 2.0 * D, tol * 10);
    }
    std::vector<P> cross;
    for (std::size_t d = 0; d < D; ++d)
        for (double s : {-1.0, 1.0}) {
            P p{};
            p[d] = T(s);
            cross.push_back(p);
        }
    cross.push_back(P{});
    const H hc = H::fit(cross);
    EXPECT_NEAR(double(hc.volume()), D == 3 ? 4.0 / 3 : 2.0, 1e-6);
    if constexpr (D == 3) {
        // A cube grid: 8 vertices, 12 triangles, 6 planes (coplanar triangles share a plane).
        std::vector<P> g;
        for (int i = 0; i < 5; ++i)
            for (int j = 0; j < 5; ++j)
                for (int k = 0; k < 5; ++k) g.push_back(P{{T(i), T(j), T(k)}});
        const H hg = H::fit(g);
        EXPECT_EQ(hg.vertices().size(), 8u);
        EXPECT_EQ(hg.facet_count(), 12u);
        EXPECT_EQ(hg.planes().size(), 6u);
        EXPECT_EQ(hg.volume(), T(64));
        EXPECT_EQ(hg.surface_area(), T(96));
    }
}

// Exact touching (cubes sharing a face, an edge, a corner; random integer hulls placed so a
// vertex lies on the other's facet plane) overlaps; a clear gap does not; penetration does.
TYPED_TEST(hull, overlaps_touching_pairs_and_gaps) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    spatial_test::seeded_rng rng(14);
    const std::vector<P> cube = sets_for<T, D>::unit_cube();
    const H a = H::fit(cube);
    const T gap = sizeof(T) == 4 ? T(1e-4) : T(1e-9);
    for (unsigned m = 1; m < (1u << D); ++m) {  // face, edge, corner contact
        P t{};
        for (std::size_t d = 0; d < D; ++d) t[d] = T((m >> d) & 1);
        const H b = a.transformed(rigid_transform<T, D>::translate(t));
        EXPECT_TRUE(a.overlaps(b)) << "contact " << m;
        EXPECT_TRUE(b.overlaps(a)) << "contact " << m;
        std::vector<P> moved;
        for (auto p : cube) {
            for (std::size_t d = 0; d < D; ++d) p[d] += t[d];
            moved.push_back(p);
        }
        EXPECT_TRUE(a.overlaps(H::fit(moved)));
        P tg = t;
        for (std::size_t d = 0; d < D; ++d)
            if (t[d] == 1) {
                tg[d] += gap;  // opens a gap along an axis of contact
                break;
            }
        EXPECT_FALSE(a.overlaps(a.transformed(rigid_transform<T, D>::translate(tg)))) << "gap " << m;
    }
    // Random integer hulls: B's lowest vertex along A's facet normal n placed on A's vertex x
    // of that facet (exact integer translation), so the hulls touch exactly.
    int contact = 0;
    for (int trial = 0; trial < 600; ++trial) {
        auto rnd_set = [&](std::size_t n) {
            std::vector<P> v(n);
            for (auto& p : v)
                for (std::size_t d = 0; d < D; ++d) p[d] = T(int(rng() % 17) - 8);
            return v;
        };
        const auto pa = rnd_set(4 + rng() % 12), pb = rnd_set(4 + rng() % 12);
        const H ha = H::fit(pa), hb = H::fit(pb);
        if (ha.affine_dimension() < int(D) || hb.affine_dimension() < int(D)) continue;
        // An exact integer outward normal of one facet of A, and a vertex x on it.
        std::array<double, 3> n{};
        std::array<double, 3> x{};
        const std::size_t facet = rng() % (D == 3 ? ha.triangles().size() : ha.vertices().size());
        if constexpr (D == 3) {
            const auto& tri = ha.triangles()[facet];
            const auto p0 = as3(ha.vertices()[tri[0]]), p1 = as3(ha.vertices()[tri[1]]), p2 = as3(ha.vertices()[tri[2]]);
            const double e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]}, e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
            n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
            x = p0;
        } else {
            const auto p0 = as3(ha.vertices()[facet]), p1 = as3(ha.vertices()[(facet + 1) % ha.vertices().size()]);
            n = {p1[1] - p0[1], p0[0] - p1[0], 0};  // outward for a CCW polygon
            x = p0;
        }
        std::size_t low = 0;
        double lowv = 1e300;
        for (std::size_t i = 0; i < hb.vertices().size(); ++i) {
            const auto b = as3(hb.vertices()[i]);
            const double s = n[0] * b[0] + n[1] * b[1] + n[2] * b[2];
            if (s < lowv) lowv = s, low = i;
        }
        P t;
        const auto bl = as3(hb.vertices()[low]);
        for (std::size_t d = 0; d < D; ++d) t[d] = T(x[d] - bl[d]);
        const H touching = hb.transformed(rigid_transform<T, D>::translate(t));
        ASSERT_TRUE(ha.overlaps(touching)) << "trial " << trial;
        ASSERT_TRUE(touching.overlaps(ha)) << "trial " << trial;
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const double amount = sizeof(T) == 4 ? 1e-3 : 1e-8;
        {  // pushed off along the normal: separated by `amount`
            P ts;
            for (std::size_t d = 0; d < D; ++d) ts[d] = T(x[d] - bl[d] + amount * n[d] / len);
            EXPECT_FALSE(ha.overlaps(hb.transformed(rigid_transform<T, D>::translate(ts)))) << "trial " << trial;
        }
        {  // B's lowest vertex just below the centre of A's facet: they overlap
            std::array<double, 3> c = x;
            if constexpr (D == 3) {
                const auto& tri = ha.triangles()[facet];
                for (int d = 0; d < 3; ++d) {
                    c[d] = 0;
                    for (int k = 0; k < 3; ++k) c[d] += as3(ha.vertices()[tri[k]])[d] / 3;
                }
            } else {
                const auto p1 = as3(ha.vertices()[(facet + 1) % ha.vertices().size()]);
                for (int d = 0; d < 2; ++d) c[d] = (x[d] + p1[d]) / 2;
            }
            P ts;
            for (std::size_t d = 0; d < D; ++d) ts[d] = T(c[d] - bl[d] - amount * n[d] / len);
            EXPECT_TRUE(ha.overlaps(hb.transformed(rigid_transform<T, D>::translate(ts)))) << "trial " << trial;
        }
        ++contact;
    }
    EXPECT_GT(contact, 250);
}

TYPED_TEST(hull, overlaps_matches_separating_axis_reference_on_random_rotated_pairs) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    spatial_test::seeded_rng rng(15);
    int both = 0, neither = 0;
    for (int trial = 0; trial < 400; ++trial) {
        auto make = [&](double cx) {
            std::vector<P> v(4 + rng() % 8);
            const rigid_transform<T, D> xf = sets_for<T, D>::random_rotation(rng, 0.5, 1e-3, 6.3);
            const double sx = 0.2 + unit(rng), sy = 0.2 + unit(rng);
            for (auto& p : v) {
                P q;
                for (std::size_t d = 0; d < D; ++d) q[d] = T((unit(rng) - 0.5) * (d == 0 ? sx : (d == 1 ? sy : 1.0)));
                p = xf.apply(q);
                p[0] += T(cx);
            }
            return H::fit(v);
        };
        const H a = make(0), b = make(0.3 + 1.4 * unit(rng));
        std::vector<std::array<double, 3>> va, vb;
        for (const auto& p : a.vertices()) va.push_back(as3(p));
        for (const auto& p : b.vertices()) vb.push_back(as3(p));
        const double g = sat_gap<D>(va, vb);
        const bool got = a.overlaps(b);
        ASSERT_EQ(got, b.overlaps(a)) << "asymmetric, trial " << trial;
        const double clear = sizeof(T) == 4 ? 1e-4 : 1e-10;
        if (g <= 0) {
            ASSERT_TRUE(got) << "false negative, trial " << trial << " gap " << g;
            ++both;
        } else if (g > clear) {
            ASSERT_FALSE(got) << "separated by " << g << " but reported overlapping, trial " << trial;
            ++neither;
        }
    }
    EXPECT_GT(both, 30);
    EXPECT_GT(neither, 30);
}

TYPED_TEST(hull, overlaps_with_flat_and_point_hulls) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    auto mk = sets_for<T, D>::make;
    const std::vector<P> cube = sets_for<T, D>::unit_cube();
    const H c = H::fit(cube);
    const H inside = H::fit(std::vector<P>{mk({0.5, 0.5, 0.5})});
    const H on_face = H::fit(std::vector<P>{mk({1, 0.5, 0.5})});
    const H outside = H::fit(std::vector<P>{mk({1.01, 0.5, 0.5})});
    EXPECT_TRUE(c.overlaps(inside));
    EXPECT_TRUE(inside.overlaps(c));
    EXPECT_TRUE(c.overlaps(on_face));
    EXPECT_FALSE(c.overlaps(outside));
    EXPECT_TRUE(inside.overlaps(inside));
    EXPECT_FALSE(inside.overlaps(outside));
    // A segment piercing the box without any vertex inside; one passing beside it.
    const H pierce = H::fit(std::vector<P>{mk({-1, 0.5, 0.5}), mk({2, 0.5, 0.5})});
    const H beside = H::fit(std::vector<P>{mk({-1, 1.25, 0.5}), mk({2, 1.25, 0.5})});
    EXPECT_TRUE(c.overlaps(pierce));
    EXPECT_FALSE(c.overlaps(beside));
    if constexpr (D == 3) {
        // Two flat squares crossing like a plus sign (no vertex of one inside the other).
        const H s1 = H::fit(std::vector<P>{mk({-1, -1, 0}), mk({1, -1, 0}), mk({1, 1, 0}), mk({-1, 1, 0})});
        const H s2 = H::fit(std::vector<P>{mk({0, -0.5, -1}), mk({0, 0.5, -1}), mk({0, 0.5, 1}), mk({0, -0.5, 1})});
        const H s3 = H::fit(std::vector<P>{mk({0, -0.5, 0.01}), mk({0, 0.5, 0.01}), mk({0, 0.5, 1}), mk({0, -0.5, 1})});
        EXPECT_TRUE(s1.overlaps(s2));
        EXPECT_FALSE(s1.overlaps(s3));
        const H s4 = H::fit(std::vector<P>{mk({0, -0.5, 0}), mk({0, 0.5, 0}), mk({0, 0.5, 1}), mk({0, -0.5, 1})});
        EXPECT_TRUE(s1.overlaps(s4));  // touching along a segment
    }
    EXPECT_FALSE(c.overlaps(H::empty()));
    EXPECT_FALSE(H::empty().overlaps(c));
}

TYPED_TEST(hull, ray_intervals_agree_with_point_sampling) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    spatial_test::seeded_rng rng(16);
    auto u = [&] { return static_cast<T>(unit(rng)); };
    std::vector<P> pts(300);
    for (auto& p : pts)
        for (std::size_t d = 0; d < D; ++d) p[d] = u() * T(2 + d) - T(1);
    const H h = H::fit(pts);
    int hits = 0;
    for (int trial = 0; trial < 300; ++trial) {
        P o, dir;
        spatial_test::random_trial_ray(trial, u, o, dir);  // axis rays: zero and negative-zero components
        if (trial % 7 == 0) o = h.vertices()[rng() % h.vertices().size()];  // through a vertex
        T t0 = 0, t1 = 0;
        const bool hit = h.ray_interval(o, dir, t0, t1);
        // The line is sampled in T, so a sample near a plane the line crosses at a grazing
        // angle may disagree with the interval by rounding: its point must then lie within
        // rounding of the thickened boundary (plane excess evaluated in double).
        auto marginal = [&](T t) {
            double worst = -1e300, mag = 0;
            for (std::size_t d = 0; d < D; ++d) mag += std::abs(double(o[d])) + std::abs(double(t) * double(dir[d]));
            for (const auto& pl : h.planes()) {
                double e = -double(pl.offset) - double(h.tolerance());
                for (std::size_t d = 0; d < D; ++d)
                    e += double(pl.normal[d]) * (double(o[d]) + double(t) * double(dir[d]) - double(h.reference()[d]));
                worst = std::max(worst, e);
            }
            return std::abs(worst) <= 4 * double(h.tolerance()) + 16 * double(std::numeric_limits<T>::epsilon()) * mag;
        };
        if (hit) {
            ASSERT_TRUE(std::isfinite(double(t0)) && std::isfinite(double(t1)) && t0 <= t1) << trial;
            ++hits;
            const T tm = t0 + (t1 - t0) / 2;
            P mid;  // the interval's midpoint is inside
            for (std::size_t d = 0; d < D; ++d) mid[d] = o[d] + tm * dir[d];
            EXPECT_TRUE(h.contains(mid) || marginal(tm)) << trial;
        }
        for (int k = -400; k <= 400; ++k) {
            const T t = static_cast<T>(k) * T(0.02);
            P p;
            for (std::size_t d = 0; d < D; ++d) p[d] = o[d] + t * dir[d];
            if (!h.contains(p)) continue;
            if (hit && t >= t0 - T(1e-3) && t <= t1 + T(1e-3)) continue;
            EXPECT_TRUE(marginal(t)) << "an inside sample off the interval (or a missed line), trial " << trial << " t " << t
                                     << " interval " << (hit ? "hit" : "miss") << " [" << t0 << ", " << t1 << "]";
        }
    }
    EXPECT_GT(hits, 30);
    // A unit box: exact entry/exit; a grazing ray along a face is a hit; parallel outside is not.
    const std::vector<P> cube = sets_for<T, D>::unit_cube();
    const H c = H::fit(cube);
    auto mk = sets_for<T, D>::make;
    T t0, t1;
    const double slack = 4 * double(c.tolerance()) + 1e-12;  // planes are thickened by the tolerance
    ASSERT_TRUE(c.ray_interval(mk({-1, 0.5, 0.5}), mk({2, 0, -0.0}), t0, t1));
    EXPECT_NEAR(double(t0), 0.5, slack);
    EXPECT_NEAR(double(t1), 1.0, slack);
    ASSERT_TRUE(c.ray_interval(mk({-1, 1, 0.5}), mk({1, -0.0, 0}), t0, t1));  // grazing the face y = 1
    EXPECT_NEAR(double(t0), 1.0, slack);
    EXPECT_NEAR(double(t1), 2.0, slack);
    EXPECT_FALSE(c.ray_interval(mk({-1, 1.001, 0.5}), mk({1, 0, 0}), t0, t1));
    EXPECT_FALSE(H::empty().ray_interval(mk({0, 0, 0}), mk({1, 0, 0}), t0, t1));
}

TYPED_TEST(hull, distance_lower_bound_is_valid_and_tight_along_facet_normals) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    spatial_test::seeded_rng rng(17);
    std::vector<P> pts(200);
    for (auto& p : pts)
        for (std::size_t d = 0; d < D; ++d) p[d] = T(unit(rng) * 2 - 1);
    const H h = H::fit(pts);
    for (const auto& p : pts) EXPECT_EQ(h.distance_lower_bound(p), T(0));
    const auto verts = h.vertices();
    // From a facet's centroid c along its outward normal n by s: the nearest hull point is c,
    // so the distance is exactly s.
    for (int trial = 0; trial < 100; ++trial) {
        const auto& pl = h.planes()[rng() % h.planes().size()];
        std::vector<std::array<double, 3>> on;  // vertices on this plane
        for (const auto& v : verts) {
            double s = 0;
            for (std::size_t d = 0; d < D; ++d) s += double(pl.normal[d]) * (double(v[d]) - double(h.reference()[d]));
            if (std::abs(s - double(pl.offset)) <= 2 * double(h.tolerance())) on.push_back(as3(v));
        }
        ASSERT_GE(on.size(), D);
        std::array<double, 3> c{0, 0, 0};
        for (const auto& x : on)
            for (int d = 0; d < 3; ++d) c[d] += x[d] / double(on.size());
        const double s = 0.01 + 3 * unit(rng);
        P q;
        for (std::size_t d = 0; d < D; ++d) q[d] = T(c[d] + s * double(pl.normal[d]));
        const double lb = double(h.distance_lower_bound(q));
        // Valid: never above the distance to any hull point (vertices, the centroid c).
        double upper = 1e300;
        for (const auto& v : verts) upper = std::min(upper, std::sqrt(double(squared_distance(v, q))));
        double dc = 0;
        for (std::size_t d = 0; d < D; ++d) dc += (double(q[d]) - c[d]) * (double(q[d]) - c[d]);
        upper = std::min(upper, std::sqrt(dc));
        EXPECT_LE(lb, upper * (1 + 1e-6));
        EXPECT_GE(lb, s * (1 - 1e-6) - 10 * double(h.tolerance()) - 1e-12);  // and tight
    }
    // Random far points: valid against the vertex distances.
    for (int trial = 0; trial < 200; ++trial) {
        P q;
        for (std::size_t d = 0; d < D; ++d) q[d] = T(unit(rng) * 10 - 5);
        double upper = 1e300;
        for (const auto& v : verts) upper = std::min(upper, std::sqrt(double(squared_distance(v, q))));
        EXPECT_LE(double(h.distance_lower_bound(q)), upper * (1 + 1e-6));
    }
}

TYPED_TEST(hull, merged_contains_both_and_transformed_contains_moved_points) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    spatial_test::seeded_rng rng(18);
    const double offsets[3] = {0, 1e3, sizeof(T) == 4 ? 1e5 : 1e8};
    for (int trial = 0; trial < 30; ++trial) {
        const double off = offsets[trial % 3];
        auto cloud = [&](double shift) {
            std::vector<P> v(50 + rng() % 100);
            for (auto& p : v)
                for (std::size_t d = 0; d < D; ++d) p[d] = T(off + shift + unit(rng) * 2);
            return v;
        };
        const auto pa = cloud(0), pb = cloud(1.5);
        const H a = H::fit(pa), b = H::fit(pb);
        const H m = a.merged(b);
        for (const auto* s : {&pa, &pb})
            for (const auto& p : *s) ASSERT_TRUE(m.contains(p)) << "trial " << trial;
        EXPECT_GE(double(m.volume()), std::max(double(a.volume()), double(b.volume())) * (1 - 1e-5));
        EXPECT_EQ(validate(m, [&] {
                      auto all = pa;
                      all.insert(all.end(), pb.begin(), pb.end());
                      return all;
                  }()),
                  "");
        EXPECT_TRUE(a.merged(H::empty()).contains(pa[0]));
        EXPECT_TRUE(H::empty().merged(a).contains(pa[0]));

        rigid_transform<T, D> xf = sets_for<T, D>::random_rotation(rng, 0, 0.01, 6.3);
        for (std::size_t d = 0; d < D; ++d) xf.translation[d] = T(unit(rng) * 100 - 50);
        const H moved = a.transformed(xf);
        for (const auto& p : pa) ASSERT_TRUE(moved.contains(xf.apply(p))) << "trial " << trial;
        for (const auto& v : a.vertices()) ASSERT_TRUE(moved.contains(xf.apply(v)));
        const double rel = sizeof(T) == 4 ? 1e-3 : 1e-9;
        if (off == 0) {
            EXPECT_NEAR(double(moved.volume()), double(a.volume()), rel * double(a.volume()));
        }
        // The moved hull overlaps the refit of the moved points and vice versa.
        std::vector<P> mp;
        for (const auto& p : pa) mp.push_back(xf.apply(p));
        EXPECT_TRUE(moved.overlaps(H::fit(mp)));
    }
}

// 1e4-point sets of each distribution: fast enough, valid (sampled exact checks), and the
// same hull (vertex set) whatever the input order.
TYPED_TEST(hull, larger_sets_are_valid_and_order_independent) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    const spatial_test::logged_seed seed(19);
    std::mt19937_64 rng(seed);
    for (auto [name, pts] : sets_for<T, D>::build(seed, 10000)) {
        if (pts.size() < 1000) continue;
        SCOPED_TRACE(name);
        const H h = H::fit(pts);
        ASSERT_EQ(validate(h, pts, 200000), "");
        std::shuffle(pts.begin(), pts.end(), rng);
        const H g = H::fit(pts);
        std::set<std::array<double, 3>> a, b;
        for (const auto& v : h.vertices()) a.insert(as3(v));
        for (const auto& v : g.vertices()) b.insert(as3(v));
        EXPECT_EQ(a, b);
        EXPECT_NEAR(double(h.volume()), double(g.volume()), 1e-9 * double(h.volume()));
    }
}

// The hill-climbing support (used for plane offsets and GJK) reaches the maximum from every
// start vertex, also on hulls of near-duplicate clusters where rounding makes neighbouring
// vertices look equal (axis directions give exact ties).
TYPED_TEST(hull, support_index_reaches_the_maximum_from_any_start) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    spatial_test::seeded_rng rng(22);
    for (int trial = 0; trial < 6; ++trial) {
        std::vector<P> pts;
        for (int i = 0; i < 150; ++i) {
            P p;
            double n2 = 0;
            std::array<double, D> x;
            for (auto& c : x) c = unit(rng) * 2 - 1, n2 += c * c;
            for (std::size_t d = 0; d < D; ++d) p[d] = T(x[d] / std::sqrt(n2));  // on a sphere: all extreme
            pts.push_back(p);
            for (std::size_t d = 0; d < D; ++d)
                for (T to : {T(2), T(-2)}) {
                    P q = p;
                    q[d] = std::nextafter(q[d], to);
                    pts.push_back(q);
                }
        }
        const H h = H::fit(pts);
        const auto v = h.vertices();
        ASSERT_GT(v.size(), 32u);  // hill climbing, not the small-hull linear scan
        for (int k = 0; k < 40; ++k) {
            std::array<double, D> dir{};
            if (k < int(2 * D)) dir[std::size_t(k) / 2] = k % 2 ? -1.0 : 1.0;
            else
                for (auto& c : dir) c = unit(rng) * 2 - 1;
            double best = -1e300;
            for (const auto& x : v) {
                double s = 0;
                for (std::size_t d = 0; d < D; ++d) s += dir[d] * (double(x[d]) - double(h.reference()[d]));
                best = std::max(best, s);
            }
            for (std::uint32_t start = 0; start < v.size(); start += 7) {
                const auto i = h.support_index(dir, start);
                double s = 0;
                for (std::size_t d = 0; d < D; ++d) s += dir[d] * (double(v[i][d]) - double(h.reference()[d]));
                ASSERT_GE(s, best - 1e-14) << "trial " << trial << " direction " << k << " start " << start;
            }
        }
    }
}

TYPED_TEST(hull, rejects_non_finite_input) {
    SPATIAL_DIMS_NAMES;
    using H = typename TestFixture::hull_t;
    std::vector<P> pts(3);
    pts[1][0] = std::numeric_limits<T>::quiet_NaN();
    EXPECT_THROW(H::fit(pts), std::invalid_argument);
    pts[1][0] = std::numeric_limits<T>::infinity();
    EXPECT_THROW(H::fit(pts), std::invalid_argument);
}

// ---- predicates and GJK ---------------------------------------------------------------------

// Orientation signs against exact integer arithmetic: coordinates k / 2^20 + 2^s with small
// integers k (so every difference is an exact multiple of 2^-20), near-degenerate by
// construction (points on a common plane / line plus +-1 unit), large offsets making the
// naive floating-point determinant unreliable.
TEST(hull_predicates, orientation_signs_match_integer_arithmetic) {
    spatial_test::seeded_rng rng(20);
    __extension__ typedef __int128 i128;
    int zero3 = 0, zero2 = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double offset = std::ldexp(1.0, int(rng() % 24));  // up to 2^23: still exact
        auto coord = [&](long k) { return offset + double(k) * 0x1.0p-20; };
        long a[4][3];
        // Points on the plane z = x + 2y (+ small perturbation of the last one).
        for (auto& p : a) {
            p[0] = long(rng() % 2001) - 1000, p[1] = long(rng() % 2001) - 1000;
            p[2] = p[0] + 2 * p[1];
        }
        a[3][2] += long(rng() % 3) - 1;
        double d[4][3];
        for (int i = 0; i < 4; ++i)
            for (int k = 0; k < 3; ++k) d[i][k] = coord(a[i][k]);
        i128 u[3], v[3], w[3];
        for (int k = 0; k < 3; ++k) u[k] = a[1][k] - a[0][k], v[k] = a[2][k] - a[0][k], w[k] = a[3][k] - a[0][k];
        const i128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
        const int want3 = det > 0 ? 1 : (det < 0 ? -1 : 0);
        ASSERT_EQ(predicates::orient_3d(d[0], d[1], d[2], d[3]), want3) << "trial " << trial;
        ASSERT_EQ(predicates::orient_3d_exact(d[0], d[1], d[2], d[3]), want3) << "trial " << trial;
        zero3 += want3 == 0;
        // 2D: points on the line y = 3x (+-1 on the last).
        long b[3][2];
        for (auto& p : b) p[0] = long(rng() % 2001) - 1000, p[1] = 3 * p[0];
        b[2][1] += long(rng() % 3) - 1;
        double e[3][2];
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 2; ++k) e[i][k] = coord(b[i][k]);
        const i128 det2 = i128(b[1][0] - b[0][0]) * (b[2][1] - b[0][1]) - i128(b[1][1] - b[0][1]) * (b[2][0] - b[0][0]);
        const int want2 = det2 > 0 ? 1 : (det2 < 0 ? -1 : 0);
        ASSERT_EQ(predicates::orient_2d(e[0], e[1], e[2]), want2) << "trial " << trial;
        ASSERT_EQ(predicates::orient_2d_exact(e[0], e[1], e[2]), want2) << "trial " << trial;
        zero2 += want2 == 0;
    }
    EXPECT_GT(zero3, 1000);
    EXPECT_GT(zero2, 1000);
    // Inexact differences (the general exact path): a tiny offset against a huge one.
    const double p0[3] = {1e17, 0, 0}, p1[3] = {1e17, 1, 0}, p2[3] = {1e17, 0, 1}, p3[3] = {1e17 + 16, 0.5, 0.5};
    const double p4[3] = {1e-3, 0.25, 0.25};
    EXPECT_EQ(predicates::orient_3d(p0, p1, p2, p3), -predicates::orient_3d(p0, p2, p1, p3));
    EXPECT_NE(predicates::orient_3d(p0, p1, p2, p3), 0);
    EXPECT_NE(predicates::orient_3d_exact(p0, p1, p2, p4), 0);
    EXPECT_EQ(predicates::orient_3d_exact(p0, p1, p2, p4), -predicates::orient_3d_exact(p0, p1, p2, p3));
}

// Every stage of the adaptive predicates (the filter; B, exact determinant of rounded
// differences; C, first-order tail terms; D, the determinant from the coordinates; and the
// coplanarity certificates) against big-integer arithmetic (Boost.Multiprecision cpp_int on
// the coordinates scaled by 2^300 to integers). Inputs mix magnitudes from 2^-100 to 2^100
// so that differences do not round exactly: coplanar and collinear sets built exactly, each
// nudged by one ulp in half the trials, box corners, repeated points.
namespace {
using big = boost::multiprecision::cpp_int;
big exactly_scaled(double x) {  // x * 2^300, exactly an integer for the inputs below
    int e = 0;
    const double m = std::frexp(x, &e);                        // x = m * 2^e, 0.5 <= |m| < 1
    big r(static_cast<long long>(std::ldexp(m, 53)));          // the 53-bit integer mantissa
    const int shift = e - 53 + 300;
    if (shift >= 0) return r << shift;
    EXPECT_EQ(r % (big(1) << -shift), 0) << x << " is off the test's grid";
    return r >> -shift;
}
int big_sign(const big& x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }
int orient_3d_by_big_integers(const double* a, const double* b, const double* c, const double* d) {
    big u[3], v[3], w[3];
    for (int i = 0; i < 3; ++i) {
        const big ai = exactly_scaled(a[i]);
        u[i] = exactly_scaled(b[i]) - ai, v[i] = exactly_scaled(c[i]) - ai, w[i] = exactly_scaled(d[i]) - ai;
    }
    return big_sign(w[0] * (u[1] * v[2] - u[2] * v[1]) + w[1] * (u[2] * v[0] - u[0] * v[2]) + w[2] * (u[0] * v[1] - u[1] * v[0]));
}
int orient_2d_by_big_integers(const double* a, const double* b, const double* c) {
    const big ax = exactly_scaled(a[0]), ay = exactly_scaled(a[1]);
    return big_sign((exactly_scaled(b[0]) - ax) * (exactly_scaled(c[1]) - ay) - (exactly_scaled(b[1]) - ay) * (exactly_scaled(c[0]) - ax));
}
}  // namespace

TEST(hull_predicates, every_adaptive_stage_matches_big_integer_arithmetic_across_magnitudes) {
    spatial_test::seeded_rng rng(23);
    // A double with a 20-bit mantissa and an exponent in [-100, 100]: sums of two such with
    // exponents within 30 of each other are exact, which builds exactly coplanar points.
    auto coarse = [&](int lo, int hi) {
        const double m = double(long(rng() % (1u << 20)) - (1 << 19));
        return std::ldexp(m, lo + int(rng() % unsigned(hi - lo + 1)) - 20);
    };
    int zeros = 0, nonzeros = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        double p[4][3];
        const int kind = trial % 4;
        const int scale = int(rng() % 160) - 80;  // the set's magnitude
        const int spread = int(rng() % 60);        // how far apart the points' magnitudes are
        for (auto& q : p) {
            const int e = scale + int(rng() % unsigned(spread + 1));
            q[0] = coarse(e - 15, e), q[1] = coarse(e - 15, e);
            if (kind == 0) q[2] = q[0] + q[1];                 // the plane z = x + y, exactly
            else if (kind == 1) q[2] = coarse(e - 15, e);      // general position
            else q[2] = q[0];                                  // the plane z = x, exactly
        }
        if (kind == 3) {  // a box's corners: two x, two y, two z values
            const double x[2] = {p[0][0], p[1][0]}, y[2] = {p[0][1], p[1][1]}, z[2] = {p[2][2], p[3][2]};
            for (int k = 0; k < 4; ++k) {
                const unsigned bits = unsigned(rng() % 8);
                p[k][0] = x[bits & 1], p[k][1] = y[(bits >> 1) & 1], p[k][2] = z[(bits >> 2) & 1];
            }
        }
        if (rng() % 2) {  // 1 to 64 ulps off the plane: stages B and C decide the larger ones
            double& x = p[rng() % 4][rng() % 3];
            const double to = rng() % 2 ? 1e300 : -1e300;
            for (int ulps = 1 + int(rng() % 64); ulps > 0; --ulps) x = std::nextafter(x, to);
        }
        if (rng() % 16 == 0) std::copy(p[0], p[0] + 3, p[1 + rng() % 3]);  // a repeated point
        const int want = orient_3d_by_big_integers(p[0], p[1], p[2], p[3]);
        ASSERT_EQ(predicates::orient_3d(p[0], p[1], p[2], p[3]), want) << "trial " << trial;
        ASSERT_EQ(predicates::orient_3d_exact(p[0], p[1], p[2], p[3]), want) << "trial " << trial;
        ASSERT_EQ(predicates::orient_3d_from_coordinates(p[0], p[1], p[2], p[3]), want) << "trial " << trial;
        ASSERT_EQ(predicates::orient_3d_exact(p[1], p[0], p[2], p[3]), -want) << "trial " << trial;  // a swap flips it
        if (predicates::certainly_coplanar(p[0], p[1], p[2], p[3])) {
            ASSERT_EQ(want, 0) << "trial " << trial;
        }
        (want == 0 ? zeros : nonzeros) += 1;
        // 2D: the first three points' (x, z) on the plane z = x (kind 2) are collinear.
        const double a2[2] = {p[0][0], p[0][2]}, b2[2] = {p[1][0], p[1][2]}, c2[2] = {p[2][0], p[2][2]};
        const int want2 = orient_2d_by_big_integers(a2, b2, c2);
        ASSERT_EQ(predicates::orient_2d(a2, b2, c2), want2) << "trial " << trial;
        ASSERT_EQ(predicates::orient_2d_exact(a2, b2, c2), want2) << "trial " << trial;
    }
    EXPECT_GT(zeros, 4000);
    EXPECT_GT(nonzeros, 4000);
}

TEST(hull_predicates, hull_2d_is_exact_on_nearly_collinear_points) {
    // Points on a line at an offset of 1e8 with one point 1 ulp off it: the hull is a
    // triangle exactly when that point is strictly off the line.
    std::vector<point<double, 2>> pts;
    for (int i = 0; i < 50; ++i) pts.push_back({{1e8 + i * 0.5, 1e8 + i * 0.5}});
    EXPECT_EQ(hull_2d(std::span<const point<double, 2>>(pts)).size(), 2u);
    pts.push_back({{1e8 + 10, std::nextafter(1e8 + 10, 2e8)}});
    const auto h = hull_2d(std::span<const point<double, 2>>(pts));
    ASSERT_EQ(h.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_GT(orientation_2d(h[i], h[(i + 1) % 3], h[(i + 2) % 3]), 0);
}

// Found by fuzzing (fuzz/operations on bvh<box, convex_hull> and bvh<point, convex_hull>,
// docs/fuzzing.md): the exact predicates are exact only while no product underflows (their
// header: coordinates and differences within about 1e-90 .. 1e90), and Quickhull built a wrong
// hull from coordinates outside that range: the corners of a box of denormal width were half
// outside it, and points mixing denormals, 1e-30 and 1e30 made it read past its triangle list
// (a crash under AddressSanitizer).
TEST(hull_predicates, fit_contains_every_point_whatever_the_magnitudes) {
    using H = convex_hull<double, 3>;
    using P = point<double, 3>;
    const double denormal = std::numeric_limits<double>::denorm_min();
    std::vector<P> box;
    for (int m = 0; m < 8; ++m) box.push_back(P{{m & 1 ? denormal : 0.0, m & 2 ? 2.0 : 0.0, m & 4 ? 0.5 : 0.0}});
    const std::vector<P> mixed{P{{0x0.012688b70e62bp-1022, -123456.789, 1e-30}}, P{{-denormal, 1e30, 0}},
                               P{{0, 0, 0}}, P{{0, 0, 0}}, P{{0, 0, 0}}};
    for (const std::vector<P>* pts : std::array<const std::vector<P>*, 2>{&box, &mixed}) {
        const H h = H::fit(std::span<const P>(*pts));
        for (const P& p : *pts) EXPECT_EQ(h.distance_lower_bound(p), 0.0) << p;
    }
}

// Found by the soak (bvh<point, convex_hull>, docs/fuzzing.md run 14): a hull a few
// denormals thick in one axis and about 1e-30 in another has facet normals whose raw
// components are near 1e-160 and below; their squares lost their precision in the denormals,
// the normalised normal came out longer than 1, and distance_lower_bound exceeded the true
// distance, so the bvh pruned a ball that reaches the points (exactly, in the oracle's
// rounded squared distance).
TEST(hull_predicates, distance_lower_bound_holds_for_a_hull_a_few_denormals_thick) {
    using H = convex_hull<double, 3>;
    using P = point<double, 3>;
    const std::vector<P> sliver{P{{0x1p+1, 0x1p-1022, 0x1.4484bfeebc2ap-100}},
                                P{{0x1p+1, 0x0.0000000000001p-1022, -0x1.4484bfeebc2ap-100}},
                                P{{0x1p+1, -0x0.0000000000001p-1022, -0x0.0000000000001p-1022}}};
    const H h = H::fit(std::span<const P>(sliver));
    const P far{{0x1p+1, 0x1.93e5939a08ceap+99, 0x1p+0}};
    for (const P& p : sliver) {
        EXPECT_EQ(h.distance_lower_bound(p), 0.0) << p;
        EXPECT_LE(h.distance_lower_bound(far), std::sqrt(squared_distance(far, p))) << p;
    }
}

TEST(hull_gjk, generic_support_functions_on_spheres) {
    spatial_test::seeded_rng rng(21);
    int yes = 0, no = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        std::array<double, 3> c1{unit(rng), unit(rng), unit(rng)}, c2{unit(rng) * 3, unit(rng) * 3, unit(rng) * 3};
        const double r1 = 0.1 + unit(rng), r2 = 0.1 + unit(rng);
        auto ball = [](const std::array<double, 3>& c, double r) {
            return [c, r](const std::array<double, 3>& d) {
                const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                return std::array<double, 3>{c[0] + r * d[0] / n, c[1] + r * d[1] / n, c[2] + r * d[2] / n};
            };
        };
        double dist = 0;
        for (int i = 0; i < 3; ++i) dist += (c1[i] - c2[i]) * (c1[i] - c2[i]);
        dist = std::sqrt(dist) - r1 - r2;
        // Smooth sets converge only asymptotically: tolerance 1e-6, decide outside it.
        const bool got = gjk_intersect<3>(ball(c1, r1), ball(c2, r2), std::array<double, 3>{1, 0, 0}, 1e-6, 256);
        if (dist <= 0) {
            ASSERT_TRUE(got) << trial;
            ++yes;
        } else if (dist > 1e-4) {
            ASSERT_FALSE(got) << trial << " distance " << dist;
            ++no;
        }
    }
    EXPECT_GT(yes, 100);
    EXPECT_GT(no, 100);
}

}  // namespace
