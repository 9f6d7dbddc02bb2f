// CGAL as the oracle for bounding-volume fits and overlap tests (declared in
// harness/include/harness/bv_oracles.hpp). One translation unit, so CGAL's slow headers and
// its -frounding-math stay here.
//
//   minimum ball        CGAL::Min_sphere_of_spheres_d (Fischer & Gartner's algorithm)
//   convex hull         CGAL::convex_hull_2 / convex_hull_3 into a Surface_mesh (Epick)
//   oriented box        CGAL::oriented_bounding_box (Chang, Gorissen & Melchior 2011)
//   min ellipsoid       CGAL::Approximate_min_ellipsoid_d (Khachiyan's algorithm, eps given)
//   hulls intersect     a linear feasibility program solved exactly (CGAL's QP solver with
//                       Gmpzf): conv(A) and conv(B) meet iff some convex combination of A
//                       equals some convex combination of B. Exact for any input, including
//                       flat and touching sets, and the same code in 2D and 3D.

#include "harness/bv_oracles.hpp"

// Eigen first, through the header that silences GCC 12's false warnings from its AVX-512
// intrinsics (spatial/bv/eigen_dense.hpp): CGAL's oriented_bounding_box would include it
// here otherwise, outside that header's pragmas (hundreds of warnings on an AVX-512 machine).
#include "spatial/bv/eigen_dense.hpp"

#include <CGAL/Approximate_min_ellipsoid_d.h>
#include <CGAL/Approximate_min_ellipsoid_d_traits_2.h>
#include <CGAL/Approximate_min_ellipsoid_d_traits_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Gmpzf.h>
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_2.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_3.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/optimal_bounding_box.h>
#include <CGAL/MP_Float.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace harness {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

template <std::size_t D, class Traits>
oracle_ball min_sphere_impl(std::span<const std::array<double, D>> pts) {
    using Sphere = typename Traits::Sphere;
    using Point = typename Traits::Point;
    std::vector<Sphere> s;
    s.reserve(pts.size());
    for (const auto& p : pts) {
        if constexpr (D == 2)
            s.emplace_back(Point(p[0], p[1]), 0.0);
        else
            s.emplace_back(Point(p[0], p[1], p[2]), 0.0);
    }
    const auto t0 = clock_type::now();
    CGAL::Min_sphere_of_spheres_d<Traits> ms(s.begin(), s.end());
    oracle_ball out;
    out.radius = CGAL::to_double(ms.radius());
    out.seconds = seconds_since(t0);
    for (auto it = ms.center_cartesian_begin(); it != ms.center_cartesian_end(); ++it) out.center.push_back(CGAL::to_double(*it));
    return out;
}

template <std::size_t D, class Traits>
oracle_ellipsoid min_ellipsoid_impl(std::span<const std::array<double, D>> pts, double eps) {
    using Point = std::conditional_t<D == 2, K::Point_2, K::Point_3>;
    std::vector<Point> p;
    p.reserve(pts.size());
    for (const auto& q : pts) {
        if constexpr (D == 2)
            p.emplace_back(q[0], q[1]);
        else
            p.emplace_back(q[0], q[1], q[2]);
    }
    const auto t0 = clock_type::now();
    Traits traits;
    CGAL::Approximate_min_ellipsoid_d<Traits> ame(eps, p.begin(), p.end(), traits);
    oracle_ellipsoid out;
    out.seconds = seconds_since(t0);
    out.full_dimensional = ame.is_full_dimensional();
    if (!out.full_dimensional) return out;
    double prod = 1;
    for (auto it = ame.axes_lengths_begin(); it != ame.axes_lengths_end(); ++it) prod *= *it;
    const double unit = std::pow(std::numbers::pi, D / 2.0) / std::tgamma(D / 2.0 + 1);
    out.volume = unit * prod;
    return out;
}

template <std::size_t D>
bool hulls_intersect_impl(std::span<const std::array<double, D>> a, std::span<const std::array<double, D>> b) {
    if (a.empty() || b.empty()) return false;
    // Variables: lambda_0..lambda_{na-1}, mu_0..mu_{nb-1} >= 0.
    // Rows: sum lambda = 1; sum mu = 1; for each axis d: sum lambda a_d - sum mu b_d = 0.
    using Program = CGAL::Quadratic_program<double>;
    Program lp(CGAL::EQUAL, true, 0, false, 0);
    const int na = static_cast<int>(a.size()), nb = static_cast<int>(b.size());
    for (int i = 0; i < na; ++i) {
        lp.set_a(i, 0, 1.0);
        for (std::size_t d = 0; d < D; ++d) lp.set_a(i, static_cast<int>(2 + d), a[static_cast<std::size_t>(i)][d]);
    }
    for (int j = 0; j < nb; ++j) {
        lp.set_a(na + j, 1, 1.0);
        for (std::size_t d = 0; d < D; ++d) lp.set_a(na + j, static_cast<int>(2 + d), -b[static_cast<std::size_t>(j)][d]);
    }
    lp.set_b(0, 1.0);
    lp.set_b(1, 1.0);
    for (std::size_t d = 0; d < D; ++d) lp.set_b(static_cast<int>(2 + d), 0.0);
    const auto sol = CGAL::solve_linear_program(lp, CGAL::Gmpzf());
    return !sol.is_infeasible();
}

}  // namespace

oracle_ball cgal_min_sphere(std::span<const std::array<double, 2>> pts) {
    return min_sphere_impl<2, CGAL::Min_sphere_of_spheres_d_traits_2<K, double>>(pts);
}
oracle_ball cgal_min_sphere(std::span<const std::array<double, 3>> pts) {
    return min_sphere_impl<3, CGAL::Min_sphere_of_spheres_d_traits_3<K, double>>(pts);
}

oracle_hull<2> cgal_convex_hull(std::span<const std::array<double, 2>> pts) {
    std::vector<K::Point_2> p;
    p.reserve(pts.size());
    for (const auto& q : pts) p.emplace_back(q[0], q[1]);
    std::vector<K::Point_2> h;
    const auto t0 = clock_type::now();
    CGAL::convex_hull_2(p.begin(), p.end(), std::back_inserter(h));
    oracle_hull<2> out;
    out.seconds = seconds_since(t0);
    // Shoelace relative to the first vertex (no cancellation at large offsets).
    double area2 = 0;
    for (std::size_t i = 0; i < h.size(); ++i) {
        const auto& u = h[i];
        const auto& v = h[(i + 1) % h.size()];
        const double ux = u.x() - h[0].x(), uy = u.y() - h[0].y(), vx = v.x() - h[0].x(), vy = v.y() - h[0].y();
        area2 += ux * vy - vx * uy;
        out.vertices.push_back({u.x(), u.y()});
    }
    out.volume = h.size() >= 3 ? std::abs(area2) / 2 : 0.0;
    out.facets = h.size() >= 3 ? h.size() : (h.size() == 2 ? 1 : 0);
    return out;
}

oracle_hull<3> cgal_convex_hull(std::span<const std::array<double, 3>> pts) {
    std::vector<K::Point_3> p;
    p.reserve(pts.size());
    for (const auto& q : pts) p.emplace_back(q[0], q[1], q[2]);
    CGAL::Surface_mesh<K::Point_3> mesh;
    const auto t0 = clock_type::now();
    CGAL::convex_hull_3(p.begin(), p.end(), mesh);
    oracle_hull<3> out;
    out.seconds = seconds_since(t0);
    for (auto v : mesh.vertices()) {
        const auto& q = mesh.point(v);
        out.vertices.push_back({q.x(), q.y(), q.z()});
    }
    out.facets = mesh.number_of_faces();
    // Signed volume of the closed triangulated surface (divergence theorem), relative to
    // the first vertex for precision. A flat hull (coplanar input) has volume 0.
    if (out.vertices.size() >= 4 && CGAL::is_closed(mesh)) {
        const K::Point_3 o = mesh.point(*mesh.vertices().begin());
        double v6 = 0;
        for (auto f : mesh.faces()) {
            std::array<K::Vector_3, 3> w;
            int k = 0;
            for (auto h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh)) {
                if (k < 3) w[static_cast<std::size_t>(k)] = mesh.point(mesh.target(h)) - o;
                ++k;
            }
            if (k == 3) v6 += CGAL::scalar_product(w[0], CGAL::cross_product(w[1], w[2]));
        }
        out.volume = std::abs(v6) / 6;
    }
    return out;
}

oracle_obb cgal_oriented_bounding_box(std::span<const std::array<double, 3>> pts) {
    std::vector<K::Point_3> p;
    p.reserve(pts.size());
    for (const auto& q : pts) p.emplace_back(q[0], q[1], q[2]);
    std::array<K::Point_3, 8> c;
    const auto t0 = clock_type::now();
    CGAL::oriented_bounding_box(p, c, CGAL::parameters::use_convex_hull(true));
    oracle_obb out;
    out.seconds = seconds_since(t0);
    for (std::size_t i = 0; i < 8; ++i) out.corners[i] = {c[i].x(), c[i].y(), c[i].z()};
    // CGAL's corner order: 0..3 one face, 4..7 the opposite one, with 0-1, 0-3 and 0-5 edges.
    const double a = std::sqrt(CGAL::squared_distance(c[0], c[1]));
    const double b = std::sqrt(CGAL::squared_distance(c[0], c[3]));
    const double h = std::sqrt(CGAL::squared_distance(c[0], c[5]));
    out.volume = a * b * h;
    return out;
}

oracle_ellipsoid cgal_min_ellipsoid(std::span<const std::array<double, 2>> pts, double eps) {
    return min_ellipsoid_impl<2, CGAL::Approximate_min_ellipsoid_d_traits_2<K, CGAL::MP_Float>>(pts, eps);
}
oracle_ellipsoid cgal_min_ellipsoid(std::span<const std::array<double, 3>> pts, double eps) {
    return min_ellipsoid_impl<3, CGAL::Approximate_min_ellipsoid_d_traits_3<K, CGAL::MP_Float>>(pts, eps);
}

bool cgal_convex_hulls_intersect(std::span<const std::array<double, 2>> a, std::span<const std::array<double, 2>> b) {
    return hulls_intersect_impl<2>(a, b);
}
bool cgal_convex_hulls_intersect(std::span<const std::array<double, 3>> a, std::span<const std::array<double, 3>> b) {
    return hulls_intersect_impl<3>(a, b);
}

}  // namespace harness
