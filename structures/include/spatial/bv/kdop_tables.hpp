#pragma once
// spatial::kdop — the compile-time tables of a k-DOP's fixed integer directions, computed
// once per (D, K): the directions themselves, the bases and integer adjugates of every D of
// them (vertex enumeration), their 1-norms and nonzero counts (rounding bounds of fit), the
// minimal positive circuits of the signed directions that make overlaps_exact a Farkas
// certificate, and the geometry helpers that walk them; plus the directed rounding to T.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "spatial/bv/rounding.hpp"

namespace spatial {

namespace detail_kdop {

template <std::size_t D, std::size_t K>
constexpr bool supported() {
    if constexpr (D == 2)
        return K == 4 || K == 8 || K == 16;
    else if constexpr (D == 3)
        return K == 6 || K == 14 || K == 18 || K == 26;
    else
        return false;
}

// The direction table: axes first, then the diagonals (see the header comment).
template <std::size_t D, std::size_t K>
constexpr std::array<std::array<int, D>, K / 2> direction_table() {
    std::array<std::array<int, D>, K / 2> t{};
    std::size_t n = 0;
    for (std::size_t i = 0; i < D; ++i) t[n][i] = 1, ++n;
    if constexpr (D == 2) {
        if constexpr (K >= 8) {
            t[n++] = {1, 1};
            t[n++] = {1, -1};
        }
        if constexpr (K == 16) {
            t[n++] = {2, 1};
            t[n++] = {2, -1};
            t[n++] = {1, 2};
            t[n++] = {1, -2};
        }
    } else if constexpr (D == 3) {
        if constexpr (K == 14 || K == 26) {
            t[n++] = {1, 1, 1};
            t[n++] = {1, 1, -1};
            t[n++] = {1, -1, 1};
            t[n++] = {1, -1, -1};
        }
        if constexpr (K == 18 || K == 26) {
            t[n++] = {1, 1, 0};
            t[n++] = {1, -1, 0};
            t[n++] = {1, 0, 1};
            t[n++] = {1, 0, -1};
            t[n++] = {0, 1, 1};
            t[n++] = {0, 1, -1};
        }
    }
    return t;
}

constexpr std::size_t choose(std::size_t n, std::size_t k) {
    std::size_t r = 1;
    for (std::size_t i = 0; i < k; ++i) r = r * (n - i) / (i + 1);
    return r;
}

// A list of at most N entries built at compile time: item[0, count). The form of the basis
// and circuit tables below.
template <class Entry, std::size_t N>
struct fixed_table {
    std::array<Entry, N> item{};
    std::size_t count = 0;
    constexpr void push(const Entry& e) { item[count++] = e; }
};

// D planes with linearly independent integer normals n_idx[0..D-1] meet at
//   x = (sum_k b_k col[k]) / det,
// where col[k] are the columns of the integer adjugate of the normal matrix.
template <std::size_t D>
struct basis {
    std::array<std::size_t, D> idx{};
    std::array<std::array<int, D>, D> col{};
    int det = 0;
};

template <std::size_t D, std::size_t K>
constexpr auto make_bases() {
    constexpr std::size_t A = K / 2;
    constexpr auto dirs = direction_table<D, K>();
    fixed_table<basis<D>, choose(A, D)> t{};
    if constexpr (D == 2) {
        for (std::size_t i = 0; i < A; ++i)
            for (std::size_t j = i + 1; j < A; ++j) {
                const auto &p = dirs[i], &q = dirs[j];
                const int det = p[0] * q[1] - p[1] * q[0];
                if (det == 0) continue;
                basis<D> s;
                s.idx = {i, j};
                s.col[0] = {q[1], -q[0]};
                s.col[1] = {-p[1], p[0]};
                s.det = det;
                t.push(s);
            }
    } else {
        auto cross = [](const std::array<int, 3>& a, const std::array<int, 3>& c) {
            return std::array<int, 3>{a[1] * c[2] - a[2] * c[1], a[2] * c[0] - a[0] * c[2], a[0] * c[1] - a[1] * c[0]};
        };
        for (std::size_t i = 0; i < A; ++i)
            for (std::size_t j = i + 1; j < A; ++j)
                for (std::size_t k = j + 1; k < A; ++k) {
                    const auto jk = cross(dirs[j], dirs[k]);
                    const int det = dirs[i][0] * jk[0] + dirs[i][1] * jk[1] + dirs[i][2] * jk[2];
                    if (det == 0) continue;
                    basis<D> s;
                    s.idx = {i, j, k};
                    s.col[0] = jk;
                    s.col[1] = cross(dirs[k], dirs[i]);
                    s.col[2] = cross(dirs[i], dirs[j]);
                    s.det = det;
                    t.push(s);
                }
    }
    return t;
}

// |x_i| <= growth * max_k |b_k| for every vertex candidate: the error amplification of the
// adjugate solve, used by the rounding tolerances.
template <std::size_t D, std::size_t K>
constexpr double make_growth() {
    constexpr auto bases = make_bases<D, K>();
    double g = 1;
    for (std::size_t s = 0; s < bases.count; ++s)
        for (std::size_t i = 0; i < D; ++i) {
            int sum = 0;
            for (std::size_t k = 0; k < D; ++k)
                sum += bases.item[s].col[k][i] < 0 ? -bases.item[s].col[k][i] : bases.item[s].col[k][i];
            const int det = bases.item[s].det < 0 ? -bases.item[s].det : bases.item[s].det;
            g = std::max(g, static_cast<double>(sum) / static_cast<double>(det));
        }
    return g;
}

template <std::size_t D, std::size_t K>
constexpr std::array<double, K / 2> make_l1() {  // |n_j|_1
    constexpr auto dirs = direction_table<D, K>();
    std::array<double, K / 2> r{};
    for (std::size_t j = 0; j < K / 2; ++j)
        for (std::size_t i = 0; i < D; ++i) r[j] += dirs[j][i] < 0 ? -dirs[j][i] : dirs[j][i];
    return r;
}
template <std::size_t D, std::size_t K>
constexpr std::array<int, K / 2> make_nnz() {  // nonzero components of n_j
    constexpr auto dirs = direction_table<D, K>();
    std::array<int, K / 2> r{};
    for (std::size_t j = 0; j < K / 2; ++j)
        for (std::size_t i = 0; i < D; ++i) r[j] += dirs[j][i] != 0;
    return r;
}

// Minimal positive circuits of the signed directions {+n_j, -n_j} beyond the pairs
// {+n_j, -n_j}: sets of at most D + 1 signed normals s_i n_(j_i), minimally linearly
// dependent, with integer weights w_i > 0 and sum_i w_i s_i n_(j_i) = 0. In 3D: coplanar
// triples and quadruples in general position; in 2D: triples. Each gives a Farkas
// certificate (see kdop::overlaps_exact).
template <std::size_t D>
struct circuit {
    std::array<std::size_t, D + 1> dir{};
    std::array<int, D + 1> coef{};  // w_i s_i
    std::size_t size = 0;
};
template <std::size_t D, std::size_t K>
constexpr auto make_circuits() {
    constexpr std::size_t A = K / 2;
    constexpr auto n = direction_table<D, K>();
    fixed_table<circuit<D>, 2 * (choose(A, D + 1) + choose(A, D))> t{};
    auto add = [&](const std::array<std::size_t, D + 1>& idx, const std::array<int, D + 1>& lam, std::size_t size) {
        for (int sgn : {1, -1}) {
            circuit<D> c;
            c.size = size;
            for (std::size_t i = 0; i < size; ++i) c.dir[i] = idx[i], c.coef[i] = sgn * lam[i];
            t.push(c);
        }
    };
    if constexpr (D == 2) {
        auto det2 = [&](std::size_t a, std::size_t b) { return n[a][0] * n[b][1] - n[a][1] * n[b][0]; };
        for (std::size_t i = 0; i < A; ++i)
            for (std::size_t j = i + 1; j < A; ++j)
                for (std::size_t k = j + 1; k < A; ++k)  // no two directions are parallel
                    add({i, j, k}, {det2(j, k), det2(k, i), det2(i, j)}, 3);
    } else {
        using v3 = std::array<int, 3>;
        auto cross = [](const v3& a, const v3& b) {
            return v3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        };
        auto dot = [](const v3& a, const v3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
        auto det3 = [&](std::size_t a, std::size_t b, std::size_t c) { return dot(n[a], cross(n[b], n[c])); };
        // Coplanar triples: [v2, v3] v1 + [v3, v1] v2 + [v1, v2] v3 = 0 in their plane.
        for (std::size_t i = 0; i < A; ++i)
            for (std::size_t j = i + 1; j < A; ++j)
                for (std::size_t k = j + 1; k < A; ++k) {
                    if (det3(i, j, k) != 0) continue;
                    const v3 pl = cross(n[i], n[j]);
                    add({i, j, k, 0},
                        {dot(cross(n[j], n[k]), pl), dot(cross(n[k], n[i]), pl), dot(cross(n[i], n[j]), pl), 0}, 3);
                }
        // Quadruples with every triple independent: sum_i (-1)^i det(others) n_i = 0.
        for (std::size_t i = 0; i < A; ++i)
            for (std::size_t j = i + 1; j < A; ++j)
                for (std::size_t k = j + 1; k < A; ++k)
                    for (std::size_t l = k + 1; l < A; ++l) {
                        const std::array<int, 4> lam{det3(j, k, l), -det3(i, k, l), det3(i, j, l), -det3(i, j, k)};
                        if (lam[0] == 0 || lam[1] == 0 || lam[2] == 0 || lam[3] == 0) continue;
                        add({i, j, k, l}, lam, 4);
                    }
    }
    return t;
}

template <std::size_t D, std::size_t K>
struct geometry {
    static constexpr std::size_t A = K / 2;
    static constexpr auto dirs = direction_table<D, K>();
    static constexpr auto bases = make_bases<D, K>();
    static constexpr double growth = make_growth<D, K>();
    static constexpr std::array<double, A> l1 = make_l1<D, K>();
    static constexpr std::array<int, A> nnz = make_nnz<D, K>();
    static constexpr auto circuits = make_circuits<D, K>();

    static double l2(std::size_t j) {
        double s = 0;
        for (std::size_t i = 0; i < D; ++i) s += static_cast<double>(dirs[j][i] * dirs[j][i]);
        return std::sqrt(s);
    }
    static double dot(std::size_t j, const std::array<double, D>& x) {
        double s = 0;
        for (std::size_t i = 0; i < D; ++i)
            if (dirs[j][i] != 0) s += static_cast<double>(dirs[j][i]) * x[i];
        return s;
    }

    // Calls f(x) for every vertex candidate of the polytope {lo <= n . x <= hi} that
    // satisfies every slab within tau_unit * |n_j|_1; stops early when f returns true.
    // Candidate points may repeat (several plane triples through one vertex).
    template <class F>
    static void for_each_vertex(const std::array<double, A>& lo, const std::array<double, A>& hi, double tau_unit,
                                F&& f) {
        std::array<double, A> tau;
        for (std::size_t j = 0; j < A; ++j) tau[j] = tau_unit * l1[j];
        for (std::size_t s = 0; s < bases.count; ++s) {
            const basis<D>& bs = bases.item[s];
            // Per plane pair of the basis: the two contributions b_k col_k / det.
            std::array<std::array<std::array<double, D>, 2>, D> part;
            for (std::size_t k = 0; k < D; ++k)
                for (std::size_t side = 0; side < 2; ++side) {
                    const double b = side ? hi[bs.idx[k]] : lo[bs.idx[k]];
                    for (std::size_t i = 0; i < D; ++i)
                        part[k][side][i] = b * static_cast<double>(bs.col[k][i]) / static_cast<double>(bs.det);
                }
            for (unsigned mask = 0; mask < (1u << D); ++mask) {
                bool dup = false;  // a zero-width slab: both sides give the same vertex
                for (std::size_t k = 0; k < D; ++k)
                    if ((mask >> k & 1u) && lo[bs.idx[k]] == hi[bs.idx[k]]) dup = true;
                if (dup) continue;
                std::array<double, D> x{};
                for (std::size_t k = 0; k < D; ++k)
                    for (std::size_t i = 0; i < D; ++i) x[i] += part[k][mask >> k & 1u][i];
                bool ok = true;
                for (std::size_t j = 0; j < A && ok; ++j) {
                    bool own = false;
                    for (std::size_t k = 0; k < D; ++k) own |= bs.idx[k] == j;
                    if (own) continue;
                    const double v = dot(j, x);
                    ok = !(v < lo[j] - tau[j]) && !(v > hi[j] + tau[j]);
                }
                if (ok && f(x)) return;
            }
        }
    }

    // The tolerance unit for a slab set whose finite values are at most s in magnitude:
    // bounds the rounding of a vertex candidate's n_j . x (see for_each_vertex).
    static double tolerance_unit(double s) {
        return 8 * std::numeric_limits<double>::epsilon() * growth * std::max(s, std::numeric_limits<double>::min());
    }
};

// Rounding to T toward +inf / -inf.
using detail_rounding::round_down;  // spatial/bv/rounding.hpp
using detail_rounding::round_up;

}  // namespace detail_kdop

}  // namespace spatial
