// The bv suite (see bv_suite.hpp). Flow for one shape:
//   1. fit study: for each n, generate the shape, build its convex hull (the tightness
//      reference, checked against CGAL's), then time every type x method fit, check that it
//      contains every point, and record time, volume and tightness; CGAL's fits run on the
//      same points;
//   2. pair study: M instances of m points each, randomly rotated and placed; the truth for
//      each pair (do the instances' hulls intersect?) comes from CGAL's exact LP; for every
//      type x method x overlap test, the answers over all pairs are checked against the
//      exact intersection of the two volumes (no false negative allowed; an exact test may
//      not give a false positive either) and only then timed, each timed pass checked by a
//      checksum of WHICH pairs it called overlapping; the rays' intervals are checked against
//      contains() (inside along the chord, outside just beyond its ends) and timed likewise;
//   3. rows are written atomically when the whole suite has passed.

#include "harness/bv_suite.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "spatial/bv/eigen_dense.hpp"

#include "datasets/point_set_io.hpp"
#include "datasets/random.hpp"
#include "datasets/shapes.hpp"
#include "harness/bv_oracles.hpp"
#include "harness/csv_writer.hpp"
#include "harness/fault_injection.hpp"
#include "harness/progress.hpp"
#include "harness/run_info.hpp"
#include "harness/suite_cases.hpp"
#include "harness/suite_context.hpp"
#include "harness/timing.hpp"
#include "harness/validation.hpp"
#include "spatial/bv/aabb.hpp"
#include "spatial/bv/convex_hull.hpp"
#include "spatial/bv/ellipsoid.hpp"
#include "spatial/bv/kdop.hpp"
#include "spatial/bv/obb.hpp"
#include "spatial/bv/sphere.hpp"

namespace harness {
namespace {

using P = spatial::point<double, 3>;
using vec3 = std::array<double, 3>;

struct preset_config {
    std::vector<std::size_t> sizes;   // fit study
    std::size_t fit_repetitions;
    std::size_t instances;            // pair study: M instances ...
    std::size_t instance_points;      // ... of m points each
    std::size_t rays;                 // lines per instance set
    std::size_t cgal_ellipsoid_max_n; // CGAL's Approximate_min_ellipsoid_d is slow (8-10 s at 1e6)
    std::size_t cgal_hull_shell_max_n;// CGAL's hull on a thin shell (14-18 s at 1e6)
    std::vector<std::string> real_meshes;
};

preset_config preset(const std::string& name) {
    const std::vector<std::string> meshes{"bunny00.off", "refined_elephant.off", "armadillo.off"};
    if (name == "smoke") return {{1000}, 1, 12, 64, 64, 1000, 1000, {}};
    if (name == "quick") return {{1000, 10000, 100000, 1000000}, 3, 40, 200, 400, 100000, 1000000, meshes};
    if (name == "full") return {{1000, 10000, 100000, 1000000}, 5, 64, 400, 1000, 1000000, 1000000, meshes};
    throw std::invalid_argument("unknown preset '" + name + "' (expected smoke, quick or full)");
}

std::vector<vec3> to_arrays(std::span<const P> pts) {
    std::vector<vec3> v(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) v[i] = pts[i].coords;
    return v;
}

// ---------------------------------------------------------------------------------------
// One fitting method of one volume type, and the volume type's description.

template <class BV>
struct fit_method {
    std::string name;
    std::function<BV(std::span<const P>)> fit;
    bool exact_vs_cgal = false;  // checked against CGAL's answer
};

template <class BV>
struct overlap_test {
    std::string name;
    bool (*test)(const BV&, const BV&);
    // An exact test must agree with the exact reference both ways (no false positive either);
    // a conservative one only may not miss.
    bool exact = false;
};

// Exact reference for "do these two volumes intersect?": 1 yes, 0 no, -1 too close to call
// (within rounding of touching: such pairs can never be counted as false negatives or
// false positives).
template <class BV>
struct volume_type {
    std::string name;
    std::vector<fit_method<BV>> methods;
    std::vector<overlap_test<BV>> tests;
    std::function<int(const BV&, const BV&)> exact_intersect;
};

// Polytopes: CGAL's exact LP on the vertex sets, after a cheap disjoint-bounding-box exit.
int polytopes_intersect(const std::vector<vec3>& a, const std::vector<vec3>& b) {
    for (int d = 0; d < 3; ++d) {
        double alo = INFINITY, ahi = -INFINITY, blo = INFINITY, bhi = -INFINITY;
        for (const auto& p : a) alo = std::min(alo, p[d]), ahi = std::max(ahi, p[d]);
        for (const auto& p : b) blo = std::min(blo, p[d]), bhi = std::max(bhi, p[d]);
        if (ahi < blo || bhi < alo) return 0;
    }
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    return cgal_convex_hulls_intersect(a, b) ? 1 : 0;
#else
    throw std::logic_error("the bv suite's exact polytope reference needs CGAL (configure with SPATIAL_WITH_CGAL=ON)");
#endif
}

// Balls: squared centre distance against squared radius sum, in long double; within a
// relative 1e-12 band the pair is "touching" and left undecided.
int balls_intersect(const spatial::sphere<double, 3>& a, const spatial::sphere<double, 3>& b) {
    long double d2 = 0;
    for (int i = 0; i < 3; ++i) {
        const long double e = static_cast<long double>(a.center[i]) - static_cast<long double>(b.center[i]);
        d2 += e * e;
    }
    const long double s = static_cast<long double>(a.radius) + static_cast<long double>(b.radius);
    const long double gap = d2 - s * s;
    if (std::abs(gap) <= 1e-12L * (d2 + s * s)) return -1;
    return gap < 0 ? 1 : 0;
}

// Ellipsoids: the Perram & Wertheim (1985) contact function, an independent implementation
// in long double: with shape matrices A, B (x inside iff (x - c)^T A (x - c) <= 1) and
// r = c_B - c_A, F(l) = l (1 - l) r^T [(1 - l) A^-1 + l B^-1]^-1 r is concave on [0, 1] and
// the ellipsoids intersect iff max F <= 1. Golden-section search to 1e-15 in l.
using mat3l = Eigen::Matrix<long double, 3, 3>;
using vec3l = Eigen::Matrix<long double, 3, 1>;
mat3l inverse_shape(const spatial::ellipsoid<double, 3>& e) {  // A^-1 = U diag(a_k^2) U^T
    mat3l m = mat3l::Zero();
    for (int k = 0; k < 3; ++k) {
        vec3l u;
        for (int d = 0; d < 3; ++d) u[d] = e.axes[static_cast<std::size_t>(k)][static_cast<std::size_t>(d)];
        const long double a = e.semi_axes[static_cast<std::size_t>(k)];
        m += a * a * u * u.transpose();
    }
    return m;
}
int ellipsoids_intersect(const spatial::ellipsoid<double, 3>& a, const spatial::ellipsoid<double, 3>& b) {
    const mat3l ai = inverse_shape(a), bi = inverse_shape(b);
    vec3l r;
    for (int d = 0; d < 3; ++d) r[d] = static_cast<long double>(b.center[d]) - static_cast<long double>(a.center[d]);
    auto f = [&](long double l) -> long double {
        const mat3l m = (1 - l) * ai + l * bi;
        return l * (1 - l) * r.dot(m.ldlt().solve(r));
    };
    long double lo = 0, hi = 1;
    const long double g = (std::sqrt(5.0L) - 1) / 2;
    long double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = f(x1), f2 = f(x2);
    while (hi - lo > 1e-15L) {
        if (f1 < f2) lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = f(x2);
        else hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = f(x1);
    }
    const long double fmax = std::max(f1, f2);
    if (std::abs(fmax - 1) <= 1e-9L) return -1;
    return fmax <= 1 ? 1 : 0;
}

template <class BV>
std::vector<vec3> corners_of(const BV& b) {
    std::vector<vec3> v;
    if constexpr (std::is_same_v<BV, spatial::aabb<double, 3>>) {
        for (int m = 0; m < 8; ++m) v.push_back({m & 1 ? b.hi[0] : b.lo[0], m & 2 ? b.hi[1] : b.lo[1], m & 4 ? b.hi[2] : b.lo[2]});
    } else if constexpr (std::is_same_v<BV, spatial::obb<double, 3>>) {
        for (const auto& c : b.corners()) v.push_back(c.coords);
    } else {
        for (const auto& c : b.vertices()) v.push_back(c.coords);
    }
    return v;
}

template <class BV>
std::function<int(const BV&, const BV&)> polytope_reference() {
    return [](const BV& a, const BV& b) { return polytopes_intersect(corners_of(a), corners_of(b)); };
}

// ---------------------------------------------------------------------------------------

using context = suite_context<preset_config>;

std::string fmt(double v) {
    std::ostringstream os;
    os.precision(4);
    os << v;
    return os.str();
}

// The shape's reference hull on n points: ours, checked against CGAL's (volume and vertex
// count) when CGAL is present.
struct hull_reference {
    double volume = 0;
};

// ---------------------------------------------------------------------------------------
// Fit study of one volume type on one point set.

template <class BV>
void fit_study(context& ctx, const volume_type<BV>& type, const std::string& workload, std::span<const P> pts,
               double hull_volume, const spatial::sphere<double, 3>* cgal_ball) {
    for (const auto& m : type.methods) {
        BV fitted{};
        bool checked = false;
        double first_volume = 0;
        std::size_t contained = 0;  // points checked for containment
        const auto t = time_repeated(
            pts.size() >= 1000000 ? 0 : 1, ctx.cfg.fit_repetitions, [] {}, [&] { return fitted = m.fit(pts); },
            [&](const BV& b) {
                // The first answer is checked point by point; every later repetition must
                // reproduce it (the fits are deterministic), which its volume shows.
                if (checked) {
                    if (static_cast<double>(b.volume()) != first_volume)
                        throw validation_error("bv " + type.name + " method " + m.name + " on " + workload +
                                               ": a repetition gave a different volume");
                    return;
                }
                checked = true;
                first_volume = static_cast<double>(b.volume());
                // Containment of every point, except for the convex hull beyond n x facets =
                // 1e9 (its contains() is O(facets)): then a deterministic stride sample of
                // ~1e9 / facets points, plus the exactness checks against CGAL's hull.
                std::size_t stride = 1;
                if constexpr (requires { b.facet_count(); }) {
                    const double work = static_cast<double>(pts.size()) * static_cast<double>(std::max<std::size_t>(1, b.facet_count()));
                    if (work > 1e9) stride = static_cast<std::size_t>(std::ceil(work / 1e9));
                }
                for (std::size_t i = 0; i < pts.size(); i += stride, ++contained)
                    if (!b.contains(pts[i]))
                        throw validation_error("bv " + type.name + " method " + m.name + " on " + workload + " n=" +
                                               std::to_string(pts.size()) + ": point " + std::to_string(i) +
                                               " is outside the fitted volume");
            });
        const double vol = static_cast<double>(fitted.volume());
        if (!std::isfinite(vol) || vol < 0)
            throw validation_error("bv " + type.name + " method " + m.name + " on " + workload + ": volume " + fmt(vol));
        if constexpr (std::is_same_v<BV, spatial::sphere<double, 3>>) {
            if (m.exact_vs_cgal && cgal_ball) {
                const double r = fitted.radius, rc = cgal_ball->radius;
                if (std::abs(r - rc) > 1e-9 * std::max(1.0, rc) + 1e-7 * rc)
                    throw validation_error("minimum ball on " + workload + " n=" + std::to_string(pts.size()) + ": radius " +
                                           fmt(r) + " but CGAL's Min_sphere_of_spheres_d gives " + fmt(rc));
            }
        }
        const std::string params = "method=" + m.name;
        const row_scope scope = ctx.scope(workload, pts.size())
                                    .with_check(contained == pts.size() ? check::containment_all
                                                                        : check::containment_sample(contained));
        ctx.rows.push_back(scope.timed("spatialbench", type.name, "fit", params, "fit_time", t, "s"));
        ctx.rows.push_back(scope.figure("spatialbench", type.name, "fit", params, "volume", vol, "u^3"));
        if (hull_volume > 0)
            ctx.rows.push_back(scope.figure("spatialbench", type.name, "fit", params, "tightness", vol / hull_volume, "ratio"));
    }
}

// How many passes of `pass` make a timed repetition of ~2 ms (at least one).
template <class Pass>
std::size_t calibrate_loops(Pass&& pass) {
    const auto t0 = std::chrono::steady_clock::now();
    volatile std::size_t sink = pass();
    (void)sink;
    const double one = std::max(seconds_since(t0), 1e-9);
    return std::max<std::size_t>(1, static_cast<std::size_t>(2e-3 / one));
}

// ---------------------------------------------------------------------------------------
// Pair study: instances, their hulls, and the exact truth per pair.

struct instance_set {
    std::vector<std::vector<P>> points;
    std::vector<spatial::convex_hull<double, 3>> hulls;
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    std::vector<char> shapes_meet;  // per pair: do the instances' hulls intersect (exact)?
    std::vector<std::pair<P, P>> rays;  // lines (origin, direction)
    std::size_t disjoint_pairs = 0;
};

instance_set make_instances(context& ctx, const std::string& workload, const std::vector<P>* mesh, std::uint64_t seed) {
    instance_set s;
    datasets::random_stream rng(datasets::derive_seed(seed, 0x1a57));
    const std::size_t M = ctx.cfg.instances, m = ctx.cfg.instance_points;
    const double side = 2.2;  // instances of diameter ~1 in a cube of this side: ~1/4 of pairs overlap
    for (std::size_t i = 0; i < M; ++i) {
        std::vector<P> pts;
        if (mesh) {
            const auto rot = datasets::random_rotation(rng);
            for (std::size_t j = 0; j < m; ++j) pts.push_back(rot.apply_vector((*mesh)[rng.uniform_index(mesh->size())]));
        } else {
            pts = datasets::generate_shape(workload, m, datasets::derive_seed(seed, i));
        }
        P off;
        for (int d = 0; d < 3; ++d) off[d] = side * (rng.uniform01<double>() - 0.5);
        for (auto& p : pts)
            for (int d = 0; d < 3; ++d) p[d] += off[d];
        s.hulls.push_back(spatial::convex_hull<double, 3>::fit(pts));
        s.points.push_back(std::move(pts));
    }
    for (std::size_t i = 0; i < M; ++i)
        for (std::size_t j = i + 1; j < M; ++j) {
            s.pairs.emplace_back(i, j);
            const int meet = polytopes_intersect(corners_of(s.hulls[i]), corners_of(s.hulls[j]));
            s.shapes_meet.push_back(static_cast<char>(meet));
            s.disjoint_pairs += meet == 0;
        }
    for (std::size_t r = 0; r < ctx.cfg.rays; ++r) {
        P o, d;
        for (int k = 0; k < 3; ++k) o[k] = (side + 1) * (rng.uniform01<double>() - 0.5);
        for (int k = 0; k < 3; ++k) d[k] = rng.gaussian();
        s.rays.emplace_back(o, d);
    }
    return s;
}

// The checksum of one pass's answers: the sum of (index + 1) over the questions answered yes,
// so a repetition that says yes to other questions than the validated pass differs even when
// it says yes as often.
inline std::size_t answer_checksum(std::size_t question, bool yes) { return yes ? question + 1 : 0; }

// Times `pass` (one pass over all pairs or all rays, returning the answer_checksum of its
// answers) after a warm-up, repeated so that one timed repetition lasts ~2 ms; every
// repetition must give `validated_checksum` per pass. Returns the time of ONE pass.
template <class Pass>
timing_result time_per_pass(Pass&& pass, std::size_t validated_checksum, const std::string& where) {
    const std::size_t loops = calibrate_loops(pass);
    timing_result t = time_repeated(
        1, 5, [] {},
        [&] {
            std::size_t c = 0;
            for (std::size_t l = 0; l < loops; ++l) c += pass();
            return c;
        },
        [&](std::size_t c) {
            if (c != validated_checksum * loops) throw validation_error(where + ": timed answers differ");
        });
    const double per_pass = 1.0 / static_cast<double>(loops);
    t.median_seconds *= per_pass, t.min_seconds *= per_pass, t.max_seconds *= per_pass;
    return t;
}

// Every overlap test of `type` on the volumes `bvs` fitted by `meth`: no false negative
// against the exact reference (validated on every pair), then timed; false-positive rates
// against the exact volumes and against the shapes' hulls.
template <class BV>
void overlap_study(context& ctx, const volume_type<BV>& type, const fit_method<BV>& meth, const std::string& workload,
                   const instance_set& s, const std::vector<BV>& bvs) {
    std::vector<int> exact(s.pairs.size());
    for (std::size_t p = 0; p < s.pairs.size(); ++p) exact[p] = type.exact_intersect(bvs[s.pairs[p].first], bvs[s.pairs[p].second]);
    // Every pair's answer is checked against the exact test (no false negatives).
    const row_scope scope = ctx.scope(workload, ctx.cfg.instance_points).with_check(check::exact_all);
    for (const auto& test : type.tests) {
        const std::string where = "bv " + type.name + " method " + meth.name + " test " + test.name + " on " + workload;
        const std::string params = "method=" + meth.name + ";test=" + test.name + ";instances=" + std::to_string(s.points.size());
        std::size_t positives = 0, fp_exact = 0, exact_no = 0, fp_shapes = 0, checksum = 0;
        for (std::size_t p = 0; p < s.pairs.size(); ++p) {
            const bool yes = test.test(bvs[s.pairs[p].first], bvs[s.pairs[p].second]) && !injected_fault(type.name);
            const std::string pair = "pair (" + std::to_string(s.pairs[p].first) + ", " + std::to_string(s.pairs[p].second) + ")";
            if (!yes && exact[p] == 1)
                throw validation_error(where + ": " + pair + " intersects exactly but the test says disjoint (a false negative)");
            if (test.exact && yes && exact[p] == 0)
                throw validation_error(where + ": " + pair + " is disjoint exactly but the exact test says it overlaps (a false positive)");
            positives += yes;
            checksum += answer_checksum(p, yes);
            exact_no += exact[p] == 0;
            fp_exact += yes && exact[p] == 0;
            fp_shapes += yes && s.shapes_meet[p] == 0;
        }
        const auto t = time_per_pass(
            [&] {
                std::size_t c = 0;
                for (std::size_t p = 0; p < s.pairs.size(); ++p) c += answer_checksum(p, test.test(bvs[s.pairs[p].first], bvs[s.pairs[p].second]));
                return c;
            },
            checksum, where);
        auto ratio = [](std::size_t a, std::size_t b) { return b ? static_cast<double>(a) / static_cast<double>(b) : 0.0; };
        ctx.rows.push_back(scope.timed("spatialbench", type.name, "overlap", params, "time_per_op", t, "ns",
                                       1e9 / static_cast<double>(s.pairs.size())));
        ctx.rows.push_back(scope.figure("spatialbench", type.name, "overlap", params, "positive_rate", ratio(positives, s.pairs.size()), "ratio"));
        ctx.rows.push_back(scope.figure("spatialbench", type.name, "overlap", params, "false_positive_rate_exact", ratio(fp_exact, exact_no), "ratio"));
        ctx.rows.push_back(scope.figure("spatialbench", type.name, "overlap", params, "false_positive_rate_shapes",
                                        ratio(fp_shapes, s.disjoint_pairs), "ratio"));
    }
}

// Checks one line against one volume: a hit's interval [t0, t1] is the line's chord through
// the volume — points at 1%, 50% and 99% of it are inside and points 1% of its length (plus a
// rounding margin) beyond either end are outside, unless the line only grazes the volume — and
// a miss has none of 64 samples across the domain inside.
template <class BV>
bool checked_ray(const BV& b, const P& o, const P& d, const std::string& where) {
    double t0 = 0, t1 = 0;
    auto at = [&](double t) {
        P q;
        for (int k = 0; k < 3; ++k) q[k] = o[k] + t * d[k];
        return q;
    };
    if (b.ray_interval(o, d, t0, t1)) {
        const double len = t1 - t0, margin = 1e-6 * std::max({1.0, std::abs(t0), std::abs(t1)});
        const std::string interval = " interval [" + fmt(t0) + ", " + fmt(t1) + "]";
        if (!(t0 <= t1)) throw validation_error(where + interval + " is empty");
        if (len <= margin) return true;  // a grazing line: too short to sample
        for (const double f : {0.01, 0.5, 0.99})
            if (!b.contains(at(t0 + f * len))) throw validation_error(where + interval + " is not inside the volume at " + fmt(f));
        for (const double t : {t0 - 0.01 * len - margin, t1 + 0.01 * len + margin})
            if (b.contains(at(t))) throw validation_error(where + interval + " is shorter than the chord: t=" + fmt(t) + " is inside");
        return true;
    }
    for (int k = 0; k <= 64; ++k) {
        const double tt = -4.0 + 8.0 * k / 64.0;
        if (b.contains(at(tt))) throw validation_error(where + " reported as missing, but its point at t=" + fmt(tt) + " is inside");
    }
    return false;
}

// Every line against every volume `bvs` fitted by `meth`: validated, then timed; the hit
// rate and the share of hits that miss the shape's hull.
template <class BV>
void ray_study(context& ctx, const volume_type<BV>& type, const fit_method<BV>& meth, const std::string& workload,
               const instance_set& s, const std::vector<BV>& bvs) {
    std::size_t hits = 0, hull_misses = 0, checksum = 0;
    for (std::size_t r = 0; r < s.rays.size(); ++r) {
        const auto& [o, d] = s.rays[r];
        for (std::size_t b = 0; b < bvs.size(); ++b) {
            if (!checked_ray(bvs[b], o, d, "bv " + type.name + " method " + meth.name + " on " + workload + ": ray " + std::to_string(r)))
                continue;
            ++hits;
            checksum += answer_checksum(r * bvs.size() + b, true);
            double h0 = 0, h1 = 0;
            hull_misses += !s.hulls[b].ray_interval(o, d, h0, h1);
        }
    }
    const auto t = time_per_pass(
        [&] {
            std::size_t c = 0;
            for (std::size_t r = 0; r < s.rays.size(); ++r)
                for (std::size_t b = 0; b < bvs.size(); ++b) {
                    double t0, t1;
                    c += answer_checksum(r * bvs.size() + b, bvs[b].ray_interval(s.rays[r].first, s.rays[r].second, t0, t1));
                }
            return c;
        },
        checksum, "bv " + type.name + " ray");
    const double lines = static_cast<double>(s.rays.size() * bvs.size());
    const std::string params = "method=" + meth.name + ";instances=" + std::to_string(s.points.size());
    // checked_ray: every line's answer against the volume's own containment test.
    const row_scope scope = ctx.scope(workload, ctx.cfg.instance_points).with_check(check::contains_all);
    ctx.rows.push_back(scope.timed("spatialbench", type.name, "ray", params, "time_per_op", t, "ns", 1e9 / lines));
    ctx.rows.push_back(scope.figure("spatialbench", type.name, "ray", params, "hit_rate", static_cast<double>(hits) / lines, "ratio"));
    ctx.rows.push_back(scope.figure("spatialbench", type.name, "ray", params, "false_positive_rate_shapes",
                                    hits ? static_cast<double>(hull_misses) / static_cast<double>(hits) : 0.0, "ratio"));
}

// The pair and ray studies of every fitting method of `type` on the instances.
template <class BV>
void pair_study(context& ctx, const volume_type<BV>& type, const std::string& workload, const instance_set& s) {
    for (const auto& meth : type.methods) {
        std::vector<BV> bvs;
        for (const auto& pts : s.points) bvs.push_back(meth.fit(pts));
        overlap_study(ctx, type, meth, workload, s, bvs);
        ray_study(ctx, type, meth, workload, s, bvs);
    }
}

// ---------------------------------------------------------------------------------------
// The volume types and their methods.

using aabb3 = spatial::aabb<double, 3>;
using sphere3 = spatial::sphere<double, 3>;
using obb3 = spatial::obb<double, 3>;
using ellipsoid3 = spatial::ellipsoid<double, 3>;
using hull3 = spatial::convex_hull<double, 3>;
template <std::size_t K>
using kdop3 = spatial::kdop<double, 3, K>;

template <class BV>
bool plain_overlaps(const BV& a, const BV& b) {
    return a.overlaps(b);
}
template <class BV>
bool exact_overlaps(const BV& a, const BV& b) {
    return a.overlaps_exact(b);
}

volume_type<aabb3> aabb_type() {
    return {"aabb", {{"minmax", [](std::span<const P> p) { return aabb3::fit(p); }}}, {{"slabs", plain_overlaps<aabb3>}},
            polytope_reference<aabb3>()};
}
volume_type<sphere3> sphere_type() {
    return {"sphere",
            {{"centroid_farthest", [](std::span<const P> p) { return sphere3::fit_centroid_farthest(p); }},
             {"ritter", [](std::span<const P> p) { return sphere3::fit_ritter(p); }},
             {"minimum", [](std::span<const P> p) { return sphere3::fit_minimum(p); }, true}},
            {{"distance", plain_overlaps<sphere3>}},
            balls_intersect};
}
volume_type<obb3> obb_type() {
    return {"obb",
            {{"pca", [](std::span<const P> p) { return obb3::fit_pca(p); }},
             {"principal_axes_search", [](std::span<const P> p) { return obb3::fit_principal_axes_search(p); }},
             {"dito", [](std::span<const P> p) { return obb3::fit_dito(p); }}},
            {{"sat15", plain_overlaps<obb3>}},
            polytope_reference<obb3>()};
}
template <std::size_t K>
volume_type<kdop3<K>> kdop_type() {
    return {"kdop" + std::to_string(K),
            {{"minmax", [](std::span<const P> p) { return kdop3<K>::fit(p); }}},
            {{"slabs", plain_overlaps<kdop3<K>>}, {"exact", exact_overlaps<kdop3<K>>, true}},
            polytope_reference<kdop3<K>>()};
}
volume_type<ellipsoid3> ellipsoid_type() {
    return {"ellipsoid",
            {{"pca", [](std::span<const P> p) { return ellipsoid3::fit_pca(p); }},
             {"khachiyan_1e-3", [](std::span<const P> p) { return ellipsoid3::fit_khachiyan(p, 1e-3); }}},
            {{"perram_wertheim", plain_overlaps<ellipsoid3>}},
            ellipsoids_intersect};
}
volume_type<hull3> hull_type() {
    return {"convex_hull", {{"quickhull", [](std::span<const P> p) { return hull3::fit(p); }}}, {{"exact", plain_overlaps<hull3>, true}},
            polytope_reference<hull3>()};
}

// ---------------------------------------------------------------------------------------

// Calls f(volume_type) for every volume type of the study, in table order.
template <class F>
void for_each_volume_type(F&& f) {
    f(aabb_type());
    f(sphere_type());
    f(obb_type());
    f(kdop_type<6>());
    f(kdop_type<14>());
    f(kdop_type<18>());
    f(kdop_type<26>());
    f(ellipsoid_type());
    f(hull_type());
}

#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
// One CGAL answer with what timed_cgal_fit compares between runs and the call's own time.
template <class Answer>
struct cgal_fit {
    Answer answer;
    double seconds_of() const { return answer.seconds; }
    double volume_or_radius() const {
        if constexpr (requires { answer.volume; }) return answer.volume;
        else return answer.radius;
    }
};

// A CGAL fit timed like ours (fit_study): a warm-up below 1e6 points, then fit_repetitions
// runs, the median of the CGAL call's own time (input conversion excluded). Every run is
// validated: by `check_run(answer)` when given (CGAL's oriented box comes from a randomised
// search, so its runs differ and each is checked on its own), else by giving the first run's
// volume or radius (the other fits give the same shape; CGAL's hull volume is summed in an
// order that varies between runs, hence a relative 1e-9). A run of at least
// long_run_seconds ends the measurement as in time_repeated, and a first (validated) run that
// long is the only one: CGAL's hull and oriented box of 1e6 points and its ellipsoid of 1e5
// take 2-3 s a run. Returns the first answer.
template <class Fit, class CheckRun = std::nullptr_t>
auto timed_cgal_fit(const context& ctx, std::size_t n, Fit&& fit, const std::string& where, timing_result& t,
                    CheckRun&& check_run = nullptr) {
    auto first = fit();
    if constexpr (!std::is_null_pointer_v<std::remove_cvref_t<CheckRun>>) check_run(first.answer);
    const std::size_t warmup = n >= 1000000 ? 0 : 1;
    const std::size_t runs = first.seconds_of() >= long_run_seconds ? 0 : warmup + ctx.cfg.fit_repetitions;
    std::vector<double> seconds;
    for (std::size_t r = 0; r < runs; ++r) {
        const auto again = fit();
        if constexpr (!std::is_null_pointer_v<std::remove_cvref_t<CheckRun>>) check_run(again.answer);
        else if (std::abs(again.volume_or_radius() - first.volume_or_radius()) > 1e-9 * std::abs(first.volume_or_radius()))
            throw validation_error(where + ": a repetition gave a different answer");
        const bool long_run = again.seconds_of() >= long_run_seconds;
        if (r >= warmup || long_run) seconds.push_back(again.seconds_of());
        if (long_run) break;
    }
    if (seconds.empty()) seconds.push_back(first.seconds_of());  // a long first run: the only one
    t = summarize(std::move(seconds));
    return first;
}

// Every point inside CGAL's oriented box: the box's corners, pushed out from their centre by
// a relative 1e-9 (CGAL constructs them in floating point), as a convex hull.
void require_inside_corners(std::span<const P> pts, const std::array<std::array<double, 3>, 8>& corners,
                            const std::string& where) {
    P centre{};
    for (const auto& c : corners)
        for (int d = 0; d < 3; ++d) centre[d] += c[static_cast<std::size_t>(d)] / 8;
    std::vector<P> grown;
    for (const auto& c : corners) {
        P q;
        for (int d = 0; d < 3; ++d) q[d] = centre[d] + (c[static_cast<std::size_t>(d)] - centre[d]) * (1 + 1e-9);
        grown.push_back(q);
    }
    const auto box = hull3::fit(grown);
    for (std::size_t i = 0; i < pts.size(); ++i)
        if (!box.contains(pts[i])) throw validation_error(where + ": point " + std::to_string(i) + " is outside CGAL's box");
}

// CGAL's fits on the same points, each validated before its rows and timed like ours: the
// minimum ball contains every point (returned, to check ours against), the hull matches ours
// in volume and vertex count, the oriented box contains every point, the ellipsoid's volume
// is within tolerance of ours.
sphere3 cgal_fits(context& ctx, const std::string& workload, std::span<const P> pts, const hull3& hull) {
    const std::size_t n = pts.size();
    const auto arr = to_arrays(pts);
    const double hull_volume = static_cast<double>(hull.volume());
    const std::string on = " on " + workload + " n=" + std::to_string(n);
    auto fit_rows = [&](const std::string& verified, const std::string& bv, const std::string& method,
                        const timing_result& t, double volume, bool tightness) {
        const row_scope scope = ctx.scope(workload, n).with_check(verified);
        ctx.rows.push_back(scope.timed("cgal", bv, "fit", "method=" + method, "fit_time", t, "s"));
        if (volume < 0) return;
        ctx.rows.push_back(scope.figure("cgal", bv, "fit", "method=" + method, "volume", volume, "u^3"));
        if (tightness && hull_volume > 0)
            ctx.rows.push_back(scope.figure("cgal", bv, "fit", "method=" + method, "tightness", volume / hull_volume, "ratio"));
    };
    timing_result t;
    const auto b = timed_cgal_fit(ctx, n, [&] { return cgal_fit<oracle_ball>{cgal_min_sphere(arr)}; },
                                  "CGAL's minimum ball" + on, t).answer;
    sphere3 ball;
    ball.radius = b.radius;
    for (int d = 0; d < 3; ++d) ball.center[d] = b.center[static_cast<std::size_t>(d)];
    for (const auto& p : pts)
        if (spatial::squared_distance(p, ball.center) > b.radius * b.radius * (1 + 1e-12) + 1e-300)
            throw validation_error("CGAL's minimum ball misses a point" + on);
    fit_rows(check::containment_all, "sphere", "min_sphere_of_spheres_d", t, -1, false);
    if (workload != "thin_shell" || n <= ctx.cfg.cgal_hull_shell_max_n) {
        const auto h = timed_cgal_fit(ctx, n, [&] { return cgal_fit<oracle_hull<3>>{cgal_convex_hull(arr)}; },
                                      "CGAL's convex hull" + on, t).answer;
        if (std::abs(h.volume - hull_volume) > 1e-9 * std::max(h.volume, 1e-300) || h.vertices.size() != hull.vertices().size())
            throw validation_error("convex hull" + on + ": volume " + fmt(hull_volume) + " with " +
                                   std::to_string(hull.vertices().size()) + " vertices, CGAL's convex_hull_3 " +
                                   fmt(h.volume) + " with " + std::to_string(h.vertices.size()));
        fit_rows(check::cross_all, "convex_hull", "convex_hull_3", t, h.volume, false);
    }
    const auto o = timed_cgal_fit(
                       ctx, n, [&] { return cgal_fit<oracle_obb>{cgal_oriented_bounding_box(arr)}; },
                       "CGAL's oriented bounding box" + on, t,
                       [&](const oracle_obb& box) { require_inside_corners(pts, box.corners, "CGAL's oriented bounding box" + on); })
                       .answer;
    fit_rows(check::containment_all, "obb", "oriented_bounding_box", t, o.volume, true);
    if (n <= ctx.cfg.cgal_ellipsoid_max_n) {
        const auto e = timed_cgal_fit(ctx, n, [&] { return cgal_fit<oracle_ellipsoid>{cgal_min_ellipsoid(arr, 1e-3)}; },
                                      "CGAL's minimum ellipsoid" + on, t).answer;
        if (e.full_dimensional) {
            // Both are within (1 + tolerance) of the minimum (CGAL's double arithmetic
            // overshoots its epsilon slightly: a factor 2 of slack on the tolerance).
            const double v = static_cast<double>(ellipsoid3::fit_khachiyan(pts, 1e-3).volume());
            if (e.volume < v / (1 + 2e-3) || v < e.volume / (1 + 2e-3))
                throw validation_error("minimum ellipsoid" + on + ": volume " + fmt(v) + " but CGAL's " + fmt(e.volume) +
                                       " (both should be within 0.1% of the minimum)");
            fit_rows(check::cross_all, "ellipsoid", "approximate_min_ellipsoid_d_1e-3", t, e.volume, true);
        }
    }
    return ball;
}
#endif

void run_shape(context& ctx, const std::string& workload, const std::vector<P>* mesh, std::uint64_t seed) {
    std::vector<std::size_t> sizes = ctx.cfg.sizes;
    if (mesh) sizes = {mesh->size()};
    for (std::size_t n : sizes) {
        const std::vector<P> pts = mesh ? *mesh : datasets::generate_shape(workload, n, seed);
        const std::span<const P> sp(pts);
        // The reference hull: ours, timed as the convex_hull type's fit below; checked against
        // CGAL's volume and vertex count.
        const auto hull = hull3::fit(sp);
        const double hull_volume = static_cast<double>(hull.volume());
        std::optional<sphere3> cgal_ball;
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
        cgal_ball = cgal_fits(ctx, workload, sp, hull);
#endif
        for_each_volume_type([&]<class BV>(const volume_type<BV>& type) {
            const sphere3* ball = nullptr;
            if constexpr (std::is_same_v<BV, sphere3>) ball = cgal_ball ? &*cgal_ball : nullptr;
            fit_study(ctx, type, workload, sp, hull_volume, ball);
        });
        ctx.prog.say("fit " + workload + " n=" + std::to_string(n) + " hull volume " + fmt(hull_volume));
    }
#if defined(SPATIAL_HAVE_CGAL) && SPATIAL_HAVE_CGAL
    const auto inst = make_instances(ctx, workload, mesh, seed);
    for_each_volume_type([&](const auto& type) { pair_study(ctx, type, workload, inst); });
    ctx.prog.say("pairs " + workload + ": " + std::to_string(inst.pairs.size()) + " pairs, " +
                 std::to_string(inst.disjoint_pairs) + " disjoint");
#else
    ctx.prog.say("pairs " + workload + ": skipped (the exact overlap reference needs CGAL)");
#endif
}

// A real mesh's vertices, centred and scaled to diameter ~1 (so instances compare with the
// generated shapes).
std::vector<P> normalized_mesh(const std::filesystem::path& file) {
    auto pts = datasets::load_point_set(file);
    const auto box = aabb3::fit(pts);
    double diag = 0;
    for (int d = 0; d < 3; ++d) diag += (box.hi[d] - box.lo[d]) * (box.hi[d] - box.lo[d]);
    diag = std::sqrt(diag);
    for (auto& p : pts)
        for (int d = 0; d < 3; ++d) p[d] = (p[d] - (box.lo[d] + box.hi[d]) / 2) / diag;
    return pts;
}

}  // namespace

namespace {

context make_context(const suite_options& options) {
    context ctx = make_suite_context("bv", options, preset(options.preset));
    if (!options.sizes.empty()) ctx.cfg.sizes = options.sizes;
    return ctx;
}

// The suite's independent cases: each generated shape (at every size of the preset), then
// each real mesh that is present.
std::vector<suite_case> bv_cases(context& ctx) {
    const std::vector<std::string> shapes = ctx.opt.workloads.empty() ? datasets::shape_names() : ctx.opt.workloads;
    const auto names = datasets::shape_names();
    for (const auto& w : shapes)  // fail fast on a typo, before any work
        if (std::find(names.begin(), names.end(), w) == names.end())
            throw std::invalid_argument("unknown shape '" + w +
                                        "' (expected elongated, rotated_box, sphere, clusters or thin_shell)");
    std::vector<suite_case> cases;
    const std::uint64_t seed = ctx.opt.seed;
    for (const auto& w : shapes) cases.push_back({"bv/" + w, [&ctx, w, seed] { run_shape(ctx, w, nullptr, seed); }});
    if (!ctx.opt.real_data_dir.empty())
        for (const auto& f : ctx.cfg.real_meshes) {
            const auto path = ctx.opt.real_data_dir / f;
            if (!std::filesystem::exists(path)) continue;
            const std::string stem = std::filesystem::path(f).stem().string();
            cases.push_back({"bv/real:" + stem, [&ctx, path, stem, seed] {
                                 const auto mesh = normalized_mesh(path);
                                 run_shape(ctx, stem, &mesh, seed);
                             }});
        }
    return cases;
}

}  // namespace

void run_bv_suite(const suite_options& options) {
    context ctx = make_context(options);
    std::size_t real = 0;
    if (!options.real_data_dir.empty())
        for (const auto& f : ctx.cfg.real_meshes) {
            if (std::filesystem::exists(options.real_data_dir / f)) ++real;
            else ctx.prog.say("no " + (options.real_data_dir / f).string() + " (run datasets/fetch_real_data.sh)");
        }
    ctx.run(bv_cases(ctx));
    ctx.finish({{"real_meshes", std::to_string(real)}});
}

std::vector<std::string> bv_case_ids(const suite_options& options) {
    context ctx = make_context(options);
    return ids_of(bv_cases(ctx), options);
}

}  // namespace harness
