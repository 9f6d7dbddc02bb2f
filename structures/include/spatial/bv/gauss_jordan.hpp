#pragma once
// spatial::detail::gauss_jordan — Gauss-Jordan elimination with partial pivoting on a tiny
// augmented system, in double: the affine solves of the exact minimum sphere (its circumball
// of a support set, sphere.hpp) and of GJK's closest point of a simplex (gjk.hpp), each of at
// most D unknowns.

#include <cmath>
#include <cstddef>
#include <utility>

namespace spatial::detail {

// a: n rows of n + 1 columns (the right-hand side last), a[i][j] indexable. Eliminates column
// by column with the largest remaining pivot; returns false, leaving a half-eliminated, as
// soon as usable(pivot) rejects the pivot (an affinely dependent set). On true, a is diagonal:
// x_i = a[i][n] / a[i][i].
template <class Matrix, class Usable>
bool gauss_jordan(Matrix& a, std::size_t n, Usable&& usable) {
    for (std::size_t col = 0; col < n; ++col) {
        std::size_t piv = col;
        for (std::size_t r = col + 1; r < n; ++r)
            if (std::abs(a[r][col]) > std::abs(a[piv][col])) piv = r;
        if (!usable(a[piv][col])) return false;
        if (piv != col)
            for (std::size_t j = 0; j <= n; ++j) std::swap(a[col][j], a[piv][j]);
        for (std::size_t r = 0; r < n; ++r) {
            if (r == col) continue;
            const double f = a[r][col] / a[col][col];
            for (std::size_t j = col; j <= n; ++j) a[r][j] -= f * a[col][j];
        }
    }
    return true;
}

}  // namespace spatial::detail
