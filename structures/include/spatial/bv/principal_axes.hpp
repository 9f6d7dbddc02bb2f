#pragma once
// spatial::principal_axes — the mean and the eigenvectors of the covariance matrix of a point
// set (principal component analysis), the starting frame of the PCA-fitted OBB and ellipsoid
// (Gottschalk, Lin & Manocha 1996, "OBBTree"). O(n D^2) for the covariance plus a D x D
// symmetric eigen-solve (Eigen's SelfAdjointEigenSolver).
//
// Precision: accumulated in double relative to the first point, so that sets offset by 1e8
// or with a spread of 1e-12 keep their shape. Degenerate sets (one point, all equal,
// collinear, coplanar) give zero eigenvalues and still an orthonormal right-handed frame.

#include "spatial/bv/eigen_dense.hpp"

#include <array>
#include <cstddef>
#include <span>

#include "spatial/core/point.hpp"

namespace spatial {

template <std::size_t D>
struct principal_frame {
    std::array<double, D> mean{};
    // axes[0] has the largest variance; rows are orthonormal; det = +1 (right-handed).
    std::array<std::array<double, D>, D> axes{};
    std::array<double, D> variance{};  // eigenvalues, descending
};

// Covariance of pts about their mean (double precision, relative to pts[0]).
template <class T, std::size_t D>
Eigen::Matrix<double, int(D), int(D)> covariance(std::span<const point<T, D>> pts, std::array<double, D>& mean) {
    using vec = Eigen::Matrix<double, int(D), 1>;
    Eigen::Matrix<double, int(D), int(D)> c = Eigen::Matrix<double, int(D), int(D)>::Zero();
    mean.fill(0);
    if (pts.empty()) return c;
    vec s = vec::Zero();
    for (const auto& p : pts)
        for (std::size_t d = 0; d < D; ++d) s[int(d)] += static_cast<double>(p[d]) - static_cast<double>(pts[0][d]);
    const double n = static_cast<double>(pts.size());
    const vec m = s / n;  // mean relative to pts[0]
    for (const auto& p : pts) {
        vec x;
        for (std::size_t d = 0; d < D; ++d) x[int(d)] = static_cast<double>(p[d]) - static_cast<double>(pts[0][d]) - m[int(d)];
        c.noalias() += x * x.transpose();
    }
    c /= n;
    for (std::size_t d = 0; d < D; ++d) mean[d] = static_cast<double>(pts[0][d]) + m[int(d)];
    return c;
}

template <class T, std::size_t D>
principal_frame<D> principal_axes(std::span<const point<T, D>> pts) {
    principal_frame<D> f;
    const auto c = covariance(pts, f.mean);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, int(D), int(D)>> es(c);
    // Eigen sorts eigenvalues ascending; we want descending.
    for (std::size_t k = 0; k < D; ++k) {
        const int col = int(D - 1 - k);
        f.variance[k] = std::max(0.0, es.eigenvalues()[col]);
        for (std::size_t d = 0; d < D; ++d) f.axes[k][d] = es.eigenvectors()(int(d), col);
    }
    if (es.info() != Eigen::Success) {  // cannot happen for finite input; keep a valid frame
        for (std::size_t k = 0; k < D; ++k)
            for (std::size_t d = 0; d < D; ++d) f.axes[k][d] = k == d ? 1.0 : 0.0;
    }
    // Right-handed: flip the last axis if det < 0.
    Eigen::Matrix<double, int(D), int(D)> m;
    for (std::size_t k = 0; k < D; ++k)
        for (std::size_t d = 0; d < D; ++d) m(int(k), int(d)) = f.axes[k][d];
    if (m.determinant() < 0)
        for (std::size_t d = 0; d < D; ++d) f.axes[D - 1][d] = -f.axes[D - 1][d];
    return f;
}

}  // namespace spatial
