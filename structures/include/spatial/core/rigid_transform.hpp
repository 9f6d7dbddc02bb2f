#pragma once
// spatial::rigid_transform<T, D> — a rotation followed by a translation, x -> R x + t, the
// motion of a rigid object. Bounding volumes offer transformed(xf) so that a moving object's
// volume follows it without refitting (issue 3); collision scenes use it for rigid motion.
// R is stored row-major and is assumed orthonormal (det +1); the factories build it so.

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>

#include "spatial/core/point.hpp"

namespace spatial {

template <class T, std::size_t D>
struct rigid_transform {
    SPATIAL_POINT_MEMBER_TYPES(T, D);

    std::array<std::array<T, D>, D> rotation{};  // row-major
    point_type translation{};

    static rigid_transform identity() {
        rigid_transform x;
        for (std::size_t i = 0; i < D; ++i) x.rotation[i][i] = 1;
        return x;
    }
    static rigid_transform translate(const point_type& t) {
        rigid_transform x = identity();
        x.translation = t;
        return x;
    }
    // 2D: counter-clockwise rotation by `angle` radians about the origin.
    static rigid_transform rotate(T angle) requires(D == 2) {
        rigid_transform x;
        const T c = std::cos(angle), s = std::sin(angle);
        x.rotation = {{{c, -s}, {s, c}}};
        return x;
    }
    // 3D: rotation by `angle` radians about `axis` (Rodrigues' formula); axis need not be unit.
    static rigid_transform rotate(const point_type& axis, T angle) requires(D == 3) {
        const T n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        if (!(n > 0) || !std::isfinite(n)) throw std::invalid_argument("rigid_transform::rotate: the axis must be a finite non-zero vector");
        const T x = axis[0] / n, y = axis[1] / n, z = axis[2] / n;
        const T c = std::cos(angle), s = std::sin(angle), k = 1 - c;
        rigid_transform r;
        r.rotation = {{{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
                       {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
                       {z * x * k - y * s, z * y * k + x * s, c + z * z * k}}};
        return r;
    }

    point_type apply(const point_type& p) const {  // R p + t
        point_type q = translation;
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) q[i] += rotation[i][j] * p[j];
        return q;
    }
    point_type apply_vector(const point_type& v) const {  // R v (directions, no translation)
        point_type q{};
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) q[i] += rotation[i][j] * v[j];
        return q;
    }
    // (this * o)(x) = this(o(x)).
    rigid_transform operator*(const rigid_transform& o) const {
        rigid_transform r;
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) {
                T s = 0;
                for (std::size_t k = 0; k < D; ++k) s += rotation[i][k] * o.rotation[k][j];
                r.rotation[i][j] = s;
            }
        r.translation = apply(o.translation);
        return r;
    }
    rigid_transform inverse() const {  // R^T (x - t)
        rigid_transform r;
        for (std::size_t i = 0; i < D; ++i)
            for (std::size_t j = 0; j < D; ++j) r.rotation[i][j] = rotation[j][i];
        for (std::size_t i = 0; i < D; ++i) {
            T s = 0;
            for (std::size_t j = 0; j < D; ++j) s -= rotation[j][i] * translation[j];
            r.translation[i] = s;
        }
        return r;
    }
};

}  // namespace spatial
