#pragma once
// Seeded point-set SHAPES for the bounding-volume study (the `bv` suite): each is a cloud of
// n points of diameter ~1 around the origin, in a canonical frame, plus a uniformly random
// rotation so no volume type profits from axis alignment.
//
//   elongated    uniform in a cylinder of length 2 and radius 0.15 (a needle: spheres and
//                axis boxes are loose, oriented volumes tight)
//   rotated_box  uniform in a 1 x 0.6 x 0.3 box (an OBB is exact)
//   sphere       uniform in a ball of radius 0.5 (a sphere is exact; an ellipsoid too)
//   clusters     four Gaussian clusters (sigma 0.08) with centres in the unit cube
//   thin_shell   on a sphere of radius 0.5, thickness 0.01 (every point is near the hull:
//                the worst case for hull algorithms)
// Rotation: a uniform random unit quaternion from four Gaussians (Shoemake 1992,
// "Uniform random rotations", Graphics Gems III). O(n).

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "datasets/random.hpp"
#include "spatial/core/point.hpp"
#include "spatial/core/rigid_transform.hpp"

namespace datasets {

inline std::vector<std::string> shape_names() { return {"elongated", "rotated_box", "sphere", "clusters", "thin_shell"}; }

// A uniformly random rotation of 3D space.
inline spatial::rigid_transform<double, 3> random_rotation(random_stream& rng) {
    double q[4], s = 0;
    do {
        s = 0;
        for (double& x : q) {
            x = rng.gaussian();
            s += x * x;
        }
    } while (s < 1e-12);
    s = std::sqrt(s);
    const double w = q[0] / s, x = q[1] / s, y = q[2] / s, z = q[3] / s;
    spatial::rigid_transform<double, 3> r;
    r.rotation = {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                   {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                   {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
    return r;
}

// n points of shape `name` (see the list above), rotated by a random rotation; seeded.
inline std::vector<spatial::point<double, 3>> generate_shape(std::string_view name, std::size_t n, std::uint64_t seed) {
    random_stream rng(derive_seed(seed, 0x5ba9e));
    const auto rot = random_rotation(rng);
    auto u = [&] { return rng.uniform01<double>(); };
    std::vector<spatial::point<double, 3>> out;
    out.reserve(n);
    std::array<std::array<double, 3>, 4> centres{};
    if (name == "clusters")
        for (auto& c : centres)
            for (double& x : c) x = u() - 0.5;
    for (std::size_t i = 0; i < n; ++i) {
        spatial::point<double, 3> p;
        if (name == "elongated") {
            double a, b;
            do a = 2 * u() - 1, b = 2 * u() - 1;
            while (a * a + b * b > 1);
            p = {{2 * u() - 1, 0.15 * a, 0.15 * b}};
        } else if (name == "rotated_box") {
            p = {{u() - 0.5, 0.6 * (u() - 0.5), 0.3 * (u() - 0.5)}};
        } else if (name == "sphere") {
            double a, b, c;
            do a = 2 * u() - 1, b = 2 * u() - 1, c = 2 * u() - 1;
            while (a * a + b * b + c * c > 1);
            p = {{0.5 * a, 0.5 * b, 0.5 * c}};
        } else if (name == "clusters") {
            const auto& c = centres[rng.uniform_index(4)];
            p = {{c[0] + 0.08 * rng.gaussian(), c[1] + 0.08 * rng.gaussian(), c[2] + 0.08 * rng.gaussian()}};
        } else if (name == "thin_shell") {
            double a = rng.gaussian(), b = rng.gaussian(), c = rng.gaussian();
            const double l = std::sqrt(a * a + b * b + c * c);
            const double r = 0.5 - 0.01 * u();
            if (!(l > 0)) a = 1, b = 0, c = 0;
            const double k = l > 0 ? r / l : r;
            p = {{a * k, b * k, c * k}};
        } else {
            throw std::invalid_argument("unknown shape '" + std::string(name) +
                                        "' (expected elongated, rotated_box, sphere, clusters or thin_shell)");
        }
        out.push_back(rot.apply_vector(p));
    }
    return out;
}

}  // namespace datasets
