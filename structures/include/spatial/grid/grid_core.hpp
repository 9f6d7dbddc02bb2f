#pragma once
// spatial::detail::grid_core — everything uniform_grid and hashed_grid share: the cell
// mapping, insertion of objects into every cell they overlap, and the queries. The two grids
// differ only in how cells are stored (cell_storage.hpp) and in when the cell size is chosen
// (uniform_grid: from the data, re-gridding as it grows; hashed_grid: fixed).
//
// Cell mapping: cell_i(x) = floor((x_i - origin_i) / h), clamped to the storage's range. It is
// MONOTONE in x (IEEE subtraction, division by h > 0 and floor are monotone), which is all the
// range queries need: an object overlapping a query box has a cell range overlapping the
// query's cell range. Geometric cell bounds (origin + j h) are used only where a distance or
// ray parameter bound is needed, always widened by a few ulps of the magnitudes involved.
//
// No object is reported twice although an object with extent sits in every cell it overlaps,
// and no per-query mark array is needed (queries stay const and thread-safe): an object is
// handled only in ONE canonical cell of the visited set —
//   box/ball query with cell box Q: the cell max(R.lo, Q.lo) of the object's range R;
//   kNN ring search around cell cq: the cell clamp(cq, R.lo, R.hi) (the object's nearest
//     cell in the Chebyshev ring order, visited exactly once);
//   ray: the DDA visits a monotone sequence of cell boxes B_k (each the cells its thick
//     segment [t_k, t_{k+1}] can touch). Per axis both ends of B_k move monotonically, so the
//     steps whose box meets R form one contiguous run; the object is tested at the first step
//     of that run (R misses B_{k-1}), in the cell max(R.lo, B_k.lo). Each cell is visited
//     once for the same reason (a cell is a 1-cell range).
//
// Ray casting: the 3D-DDA of Amanatides & Woo (1987) (after Cleary, Wyvill, Birtwistle & Vatti
// 1983 and Fujimoto et al. 1986): the next crossing on each axis is recomputed from the cell
// index (not accumulated, so no drift), zero and negative-zero direction components never
// step. A hit found at step k is final once its t is <= the step's exit parameter: objects span
// cells, so a hit in an early cell can lie beyond it and a later cell may hold a nearer one.
// kNN: expanding Chebyshev shells of cells around the query's cell, stopping when the k-th
// distance is within the lower bound on any cell outside the shells.
// Sparse safety: when a query's cell box would exceed the number of occupied cells (or of
// objects), it scans the occupied cells (or tests every object once) instead, and a ray whose
// DDA would visit more than about 2n cells tests every object instead; so no query costs more
// than O(min(occupied cells, n)) beyond its cell walk, even in a hashed grid spanning 1e15 cells.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "spatial/collide/pairs.hpp"
#include "spatial/core/container_base.hpp"
#include "spatial/core/distance.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/knn_result_set.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"
#include "spatial/core/slot_storage.hpp"
#include "spatial/grid/cell_storage.hpp"
#include "spatial/octree/ray_cell_clip.hpp"

namespace spatial::detail {

// The cell size heuristic shared by both grids (docs/structures/octree-and-grids.md): aim at n / objects_per_cell
// cells over the box — h = (volume / cells)^(1/D') over the D' axes of positive extent — but
// never below the mean object extent (so an object overlaps O(2^D) cells, not many), nor below
// 64 ulps of the coordinates (cells must be resolvable), then enlarge h until the dense
// array has at most 4 * target + 64 cells (thin boxes would otherwise explode on one axis).
template <class T, std::size_t D>
T choose_cell_size(const std::array<T, D>& lo, const std::array<T, D>& hi, double n, double mean_extent,
                   double objects_per_cell) {
    const double target = std::max(1.0, n / objects_per_cell);
    double volume = 1, magnitude = 0;
    int axes = 0;
    std::array<double, D> e{};
    for (std::size_t i = 0; i < D; ++i) {
        e[i] = static_cast<double>(hi[i]) - static_cast<double>(lo[i]);
        magnitude = std::max({magnitude, std::abs(static_cast<double>(lo[i])), std::abs(static_cast<double>(hi[i]))});
        if (e[i] > 0) {
            volume *= e[i];
            ++axes;
        }
    }
    double h = axes > 0 ? std::pow(volume / target, 1.0 / axes) : 0;
    if (!std::isfinite(h)) h = std::numeric_limits<double>::max() / 4;
    h = std::max(h, mean_extent);
    h = std::max(h, 64 * static_cast<double>(std::numeric_limits<T>::epsilon()) * magnitude);
    if (!(h > 0)) h = 1;  // everything at the origin: any size will do
    h = std::max(h, static_cast<double>(std::numeric_limits<T>::min()) * 1024);
    const double cap = 4 * target + 64;
    for (int guard = 0; guard < 2100; ++guard) {
        double cells = 1;
        for (std::size_t i = 0; i < D; ++i) cells *= std::max(1.0, std::ceil(e[i] / h));
        if (cells <= cap) break;
        h *= 1.25;
    }
    h = std::min(h, static_cast<double>(std::numeric_limits<T>::max()));
    return static_cast<T>(h);
}

template <stored_object O, class Cells, class Derived>
class grid_core : public container_base<Derived, O> {
    using contract_base = container_base<Derived, O>;
    friend contract_base;

public:
    SPATIAL_CONTAINER_BASE_MEMBERS(contract_base);

protected:
    using T = scalar_type;
    static constexpr std::size_t D = O::dimension;
    using coords = std::array<T, D>;
    using key = cell_key<D>;
    using box = cell_box<D>;
    static constexpr T bound_slack = 1 - 16 * std::numeric_limits<T>::epsilon();
    static constexpr T gamma = 16 * std::numeric_limits<T>::epsilon();

    struct extent {
        coords lo, hi;
    };

public:
    // ---- insertion -------------------------------------------------------------------
    // O(cells the object overlaps) amortised (uniform_grid re-grids in O(n) after the
    // count doubles or an object lands outside its box).
    iterator insert(const O& x) { return insert_one(x, site("insert")); }
    // The hint cannot make a grid insertion cheaper (finding the cell is O(1) already).
    iterator insert(const_iterator, const O& x) { return insert_one(x, site("insert(hint, x)")); }
    // Bulk: validates all first, chooses the grid ONCE for the final size and box (no
    // repeated re-gridding), stores the objects, then lists them cell by cell: the batch's
    // (cell, slot) entries are grouped by cell with a radix sort (cell_storage.hpp add_batch),
    // so each touched cell is looked up once and its list reserved once, and the lists are
    // filled in cell order. O(n + m) (dense re-grid) plus O(m) for the batch, with one
    // allocation per touched cell where a loop makes one per growth of each list.
    template <class InputIt>
    void insert(InputIt first, InputIt last) {
        if constexpr (!std::random_access_iterator<InputIt>) {
            // Single-pass or list-like input (a container's own range too): copy once so that
            // it can be validated first and read again.
            const std::vector<O> batch(first, last);
            insert(batch.begin(), batch.end());
        } else {
            const detail::call_site where = site("insert(first, last)");
            for (auto it = first; it != last; ++it) require_finite_object(*it, where);
            const auto m = static_cast<std::size_t>(last - first);
            if (m == 0) return;
            slots_.require_room_for(m, where);
            extent all = extent_of(*first);
            double extent_sum = 0;
            for (auto it = first; it != last; ++it) {
                const extent e = extent_of(*it);
                merge(all, e);
                extent_sum += max_extent(e);
            }
            derived().prepare_insert(all, m, extent_sum);
            slots_.reserve(slots_.capacity() + m);
            // Strong guarantee: if a cell list cannot grow, the batch is taken out of the cells
            // again (a slot a cell does not list is skipped there) and its slots given back,
            // latest first (each undo reverses the latest allocation exactly).
            std::vector<std::pair<slot_index, bool>> stored;
            stored.reserve(m);
            try {
                for (auto it = first; it != last; ++it) {
                    const bool reused = slots_.reuses_a_slot();
                    stored.emplace_back(slots_.allocate(*it, 0), reused);
                }
                list_batch(stored, all);
            } catch (const std::bad_alloc&) {
                for (auto it = stored.rbegin(); it != stored.rend(); ++it) {
                    remove_from_cells(it->first);
                    slots_.undo_allocate(it->first, it->second);
                }
                throw;
            }
        }
    }

    // ---- erasure ---------------------------------------------------------------------
    // O(cells of the object x their occupancy). Returns the next element.
    // Cannot fail once the free list has room (reserved first): removing from a cell list does
    // not allocate, and the re-grid after erasure is best-effort (after_erase).
    iterator erase(const_iterator pos) {
        const slot_index s = pos.slot();
        slots_.reserve_releases(1);
        remove_from_cells(s);
        slots_.release(s);
        derived().after_erase();
        return make(slots_.next_occupied(s + 1));
    }
    // Erases ALL elements equal to x: equal objects have equal boxes, hence the same first
    // cell, so one cell is scanned.
    size_type erase(const O& x) {
        require_finite_object(x, site("erase"));
        std::vector<slot_index> hits;
        collect_equal(x, hits, false);
        slots_.reserve_releases(hits.size());
        for (slot_index s : hits) {
            remove_from_cells(s);
            slots_.release(s);
        }
        if (!hits.empty()) derived().after_erase();
        return hits.size();
    }
    void clear() {
        slots_.clear();
        derived().reset_cells();
        large_.clear();
        reset_data_box();
    }

    // ---- lookup ----------------------------------------------------------------------
    iterator find(const O& x) {
        require_finite_object(x, site("find"));
        std::vector<slot_index> hits;
        collect_equal(x, hits, true);
        return hits.empty() ? end() : make(hits.front());
    }
    size_type count(const O& x) const {
        require_finite_object(x, site("count"));
        std::vector<slot_index> hits;
        collect_equal(x, hits, false);
        return hits.size();
    }

    // ---- ray cast --------------------------------------------------------------------
    // The object with the smallest hit time before info.hit_time, or end(). Cost: the cells
    // the (thick) ray crosses before the first hit, O(n^(1/D)) on a uniform grid over
    // uniform data; never more than O(occupied cells + n) (see the header comment).
    iterator intersect_object(const point_type& origin, const point_type& direction, scalar_type thickness,
                              info_type& info) const {
        require_finite(origin, site("intersect"), "ray origin");
        require_nonzero_direction(direction, site("intersect"));
        require_nonnegative(thickness, site("intersect"), "ray thickness");
        if (slots_.size() == 0) return end();
        slot_index hit = no_slot;
        auto test = [&](slot_index s) {
            if (slots_.value(s).intersect(origin, direction, thickness, info)) hit = s;
        };
        for (slot_index s : large_) test(s);  // first: a hit shortens the walk
        const box R = cells_.bounds();
        if (R.empty()) return hit == no_slot ? end() : make(hit);
        coords o, v;
        for (std::size_t i = 0; i < D; ++i) {
            o[i] = origin[i];
            v[i] = direction[i];
        }
        T t_begin = 0, t_end = info.hit_time;
        if (!clip_box<T, D>(o, v, data_lo_, data_hi_, thickness, t_begin, t_end)) return hit == no_slot ? end() : make(hit);
        auto scan_all = [&] {
            for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) test(s);
        };
        // Budget: the DDA is used while it is expected to touch fewer cells than a scan.
        const double budget = 2 * static_cast<double>(slots_.size()) + 64;
        double steps = 1, per_step = 1;
        for (std::size_t i = 0; i < D; ++i) {
            steps += static_cast<double>(std::abs(v[i])) * static_cast<double>(t_end - t_begin) / static_cast<double>(h_);
            per_step *= 1 + 2 * static_cast<double>(thickness) / static_cast<double>(h_);
        }
        if (!(steps * per_step <= budget)) {
            scan_all();
            return hit == no_slot ? end() : make(hit);
        }
        key c;
        for (std::size_t i = 0; i < D; ++i) c[i] = cell_of(o[i] + t_begin * v[i], i);
        T tk = t_begin;
        box prev;
        bool have_prev = false;
        double visited = 0;
        while (true) {
            T t_next = t_end;
            std::size_t axis = D;
            for (std::size_t i = 0; i < D; ++i) {
                if (v[i] == 0) continue;  // +0 or -0: never crosses a plane of this axis
                const std::int64_t edge = v[i] > 0 ? c[i] + 1 : c[i];
                const T plane = origin_[i] + static_cast<T>(edge) * h_;
                const T tb = (plane - o[i]) / v[i];
                if (tb < t_next) {
                    t_next = tb;
                    axis = i;
                }
            }
            if (t_next < tk) t_next = tk;
            // The cells the thick segment [tk, t_next] can touch.
            box B;
            for (std::size_t i = 0; i < D; ++i) {
                T a = o[i] + tk * v[i], b = o[i] + t_next * v[i];
                if (a > b) std::swap(a, b);
                B.lo[i] = cell_of(a - ray_clip_params<T>::pad(thickness, a, o[i]), i);
                B.hi[i] = cell_of(b + ray_clip_params<T>::pad(thickness, b, o[i]), i);
            }
            B = B.clipped(R);
            // Every step counts against the budget, an empty one too: where the cell planes
            // round together (coordinates near 1e30 with small cells) t_next stops advancing and
            // the walk would step through empty cells forever (found by the soak, issue 19).
            visited += B.empty() ? 1 : static_cast<double>(B.count());
            // Checked before the step's cells are walked: one step's box can hold more cells
            // than the budget (cells of 2^-1012 sized by points a denormal apart, then a ray
            // near 1e30 whose rounding pad spans 2^51 of them: found by the soak, issue 19).
            if (visited > budget) {  // rounding made the walk longer than estimated: finish by a scan
                scan_all();
                break;
            }
            if (!B.empty()) {
                for_each_cell(B, [&](const key& cell) {
                    if (have_prev && prev.contains(cell)) return;
                    const slot_list* list = cells_.find(cell);
                    if (!list) return;
                    for (slot_index s : *list) {
                        if constexpr (bounded_object<O>) {
                            const box Ro = range_of(extent_of(slots_.value(s)));
                            if (have_prev && Ro.overlaps(prev)) continue;  // tested at an earlier step
                            if (!is_first_cell(Ro, B, cell)) continue;
                        }
                        test(s);
                    }
                });
            }
            prev = B;
            have_prev = true;
            if (hit != no_slot && info.hit_time <= t_next) break;  // nothing nearer can follow
            if (!(t_next < t_end) || axis == D) break;
            tk = t_next;
            c[axis] += v[axis] > 0 ? 1 : -1;
        }
        return hit == no_slot ? end() : make(hit);
    }

    // ---- nearest neighbours and ranges ---------------------------------------------------
    // Expanding Chebyshev shells of cells around x's cell; stops when (1+eps) times the lower
    // bound on every unvisited cell is not below the k-th distance. O(k) cells of average
    // occupancy for data spread like the grid; a query far outside the data starts at the
    // first shell reaching the occupied cells.
    std::vector<iterator> find_nearest(const point_type& x, size_type k, scalar_type eps) const {
        require_finite(x, site("find_nearest"), "query point");
        require_nonnegative(eps, site("find_nearest"), "eps");
        std::vector<iterator> out;
        if (k == 0 || slots_.size() == 0) return out;
        const T factor = (1 + eps) * (1 + eps);
        knn_result_set<T> best(std::min<std::size_t>(k, slots_.size()));
        const std::size_t wanted = std::min<std::size_t>(k, slots_.size());
        for (slot_index s : large_) best.add(object_squared_distance(slots_.value(s), x), s);
        const box R = cells_.bounds();
        if (R.empty()) {
            for (const auto& cand : best.finish()) out.push_back(make(cand.slot));
            return out;
        }
        key cq;
        std::int64_t r0 = 0, r_max = 0;
        for (std::size_t i = 0; i < D; ++i) {
            cq[i] = cell_of(x[i], i);
            r0 = std::max({r0, R.lo[i] - cq[i], cq[i] - R.hi[i]});
            r_max = std::max({r_max, R.hi[i] - cq[i], cq[i] - R.lo[i]});
        }
        auto process = [&](const key& cell, slot_index s) {
            if constexpr (bounded_object<O>) {
                const box Ro = range_of(extent_of(slots_.value(s)));
                for (std::size_t i = 0; i < D; ++i)
                    if (std::clamp(cq[i], Ro.lo[i], Ro.hi[i]) != cell[i]) return;
            }
            best.add(object_squared_distance(slots_.value(s), x), s);
        };
        const bool blocks_pay = R.count() >= cells_worth_going_by_blocks;
        // In an empty block of a large grid: far from the data, by blocks from the first shell.
        const bool from_an_empty_block = blocks_pay && !cells_.block_occupied(block_of(cq));
        double walked = 0;  // cells of the shells so far: beyond the occupied cells, scan those
        for (std::int64_t r = r0; r <= r_max; ++r) {
            const double objects = static_cast<double>(slots_.size());
            walked += ring_count(cq, r, R);
            const bool sparse = walked > std::min(cells_.occupied_cells(), objects) + 8;
            if (from_an_empty_block || (!sparse && walked > block_walk_after && blocks_pay)) {
                // Far from the data (or in a sparse region): go on a block at a time.
                nearest_by_blocks(x, cq, r, R, wanted, factor, best, process);
                break;
            }
            if (sparse) {
                // Sparse: the shell has more cells than there are occupied cells (or objects);
                // finish over those, each object once (only those no earlier shell reached).
                if (objects < cells_.occupied_cells()) {
                    for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) {
                        const box Ro = range_of(extent_of(slots_.value(s)));
                        if (!is_large(Ro) && chebyshev_to_range(cq, Ro) >= r)
                            best.add(object_squared_distance(slots_.value(s), x), s);
                    }
                    break;
                }
                cells_.for_each_nonempty([&](const key& cell, const slot_list& list) {
                    if (chebyshev(cell, cq) < r) return;
                    for (slot_index s : list) process(cell, s);
                });
                break;
            }
            for_each_ring_cell(cq, r, R, [&](const key& cell) {
                if (const slot_list* list = cells_.find(cell))
                    for (slot_index s : *list) process(cell, s);
            });
            if (best.size() == wanted) {
                const T lb = shell_lower_bound(x, cq, r, R);
                if (!(lb * lb * bound_slack * factor < best.worst())) break;
            }
        }
        for (const auto& cand : best.finish()) out.push_back(make(cand.slot));
        return out;
    }
    // The rest of find_nearest once its shells of single cells have grown past a few blocks
    // (cell_blocks.hpp): the cells within Chebyshev distance r_done of cq are done; from
    // there, shells of BLOCKS around cq's block, an empty block skipped whole, each non-empty
    // block's non-empty cells at distance >= r_done visited once (so every object still meets
    // its one canonical cell once). After block shell rho every cell within Chebyshev
    // distance max(r_done - 1, rho * block_edge) of cq has been visited, which gives the stop
    // test its lower bound. A query between clusters now walks O(blocks) where it walked
    // O(cells). Once the shells would hold more blocks than are occupied (a hashed grid far
    // from its few blocks), the occupied blocks not yet visited are taken all at once instead.
    //
    // Within a shell the occupied blocks, and within a block its cells, are visited nearest
    // box first (the order of a best-first search, Hjaltason & Samet 1999, "Distance browsing
    // in spatial databases", kept inside each shell): the first cells met then fill the k best
    // and the rest of the shell is pruned by its box. In shell order a query between clusters
    // met a far corner block first and listed every object of its cells.
    template <class Best, class Process>
    void nearest_by_blocks(const point_type& x, const key& cq, std::int64_t r_done, const box& R, std::size_t wanted,
                           T factor, Best& best, Process& process) const {
        const key bq = block_of(cq);
        const box RB = blocks_of(R);
        std::int64_t rho0 = 0, rho_max = 0;
        for (std::size_t i = 0; i < D; ++i) {
            rho0 = std::max({rho0, RB.lo[i] - bq[i], bq[i] - RB.hi[i]});
            rho_max = std::max({rho_max, RB.hi[i] - bq[i], bq[i] - RB.lo[i]});
        }
        // A block, and within it a cell, that cannot hold an object nearer than the k-th is
        // skipped: every object met in a cell lies in that cell's box of cells.
        auto beyond = [&](T squared_lower_bound) {
            return best.size() == wanted && !(squared_lower_bound * bound_slack * factor < best.worst());
        };
        struct near_block {
            T squared_lower_bound;
            key b;
        };
        struct near_cell {
            T squared_lower_bound;
            key cell;
            const slot_list* list;
        };
        auto nearest_first = [](const auto& a, const auto& c) { return a.squared_lower_bound < c.squared_lower_bound; };
        std::vector<near_block> shell;
        std::vector<near_cell> cells;
        auto visit_block_cells = [&](const key& b) {
            cells.clear();
            cells_.for_each_nonempty_in_block(b, [&](const key& cell, const slot_list& list) {
                if (chebyshev(cell, cq) >= r_done) cells.push_back({cells_squared_lower_bound(x, box{cell, cell}), cell, &list});
            });
            std::sort(cells.begin(), cells.end(), nearest_first);
            for (const near_cell& c : cells) {
                if (beyond(c.squared_lower_bound)) return;
                for (slot_index s : *c.list) process(c.cell, s);
            }
        };
        double walked = 0;  // blocks of the shells so far
        for (std::int64_t rho = rho0; rho <= rho_max; ++rho) {
            walked += ring_count(bq, rho, RB);
            const bool sparse = walked > cells_.occupied_blocks() + 8;
            shell.clear();
            auto add_block = [&](const key& b) {
                shell.push_back({cells_squared_lower_bound(x, cells_of_block(b).clipped(R)), b});
            };
            if (sparse) {
                // More blocks in the shells than are occupied: finish over the occupied blocks no
                // earlier shell reached, all at once, nearest first.
                cells_.for_each_occupied_block([&](const key& b) {
                    if (chebyshev(b, bq) >= rho) add_block(b);
                });
            } else {
                for_each_ring_cell(bq, rho, RB, [&](const key& b) {
                    if (cells_.block_occupied(b)) add_block(b);
                });
            }
            std::sort(shell.begin(), shell.end(), nearest_first);
            for (const near_block& nb : shell) {
                if (beyond(nb.squared_lower_bound)) break;
                visit_block_cells(nb.b);
            }
            if (sparse) return;
            if (best.size() == wanted) {
                const std::int64_t covered = std::max(r_done - 1, rho * block_edge<D>);
                const T lb = shell_lower_bound(x, cq, covered, R);
                if (!(lb * lb * bound_slack * factor < best.worst())) return;
            }
        }
    }
    // Objects with object_squared_distance <= radius^2: the cells of the ball's box.
    std::vector<iterator> find_in_ball(const point_type& center, scalar_type radius) const {
        require_finite(center, site("find_in_ball"), "center");
        require_nonnegative(radius, site("find_in_ball"), "radius");
        std::vector<iterator> out;
        if (slots_.size() == 0) return out;
        const T r2 = radius * radius;
        box Q;
        for (std::size_t i = 0; i < D; ++i) {
            const T pad = radius + gamma * (std::abs(center[i]) + radius) + underflow_slack<T>;
            Q.lo[i] = cell_of(center[i] - pad, i);
            Q.hi[i] = cell_of(center[i] + pad, i);
        }
        for_each_in_query(Q, [&](slot_index s) {
            if (object_squared_distance(slots_.value(s), center) <= r2) out.push_back(make(s));
        });
        return out;
    }
    // Objects overlapping the closed box [lo, hi] (object_overlaps_box).
    std::vector<iterator> find_in_box(const point_type& lo, const point_type& hi) const {
        require_finite(lo, site("find_in_box"), "box corner lo");
        require_finite(hi, site("find_in_box"), "box corner hi");
        std::vector<iterator> out;
        if (slots_.size() == 0) return out;
        box Q;
        for (std::size_t i = 0; i < D; ++i) {  // an inverted query box still matches boxes spanning it
            const std::int64_t a = cell_of(lo[i], i), b = cell_of(hi[i], i);
            Q.lo[i] = std::min(a, b);
            Q.hi[i] = std::max(a, b);
        }
        for_each_in_query(Q, [&](slot_index s) {
            if (object_overlaps_box(slots_.value(s), lo, hi)) out.push_back(make(s));
        });
        return out;
    }

    // ---- STL basics and introspection ----------------------------------------------------
    // ---- collision pairs (collide/pairs.hpp) ---------------------------------------------
    // Self pairs by a cell join: every object is listed in each cell its box overlaps, so
    // two objects whose boxes overlap share the cell holding the lower corner of the boxes'
    // intersection (cell_of is monotone) — the pair is reported there only, hence once, with
    // no hash set of seen pairs. Candidates: pairs whose boxes overlap; exact adds the narrow
    // phase. O(sum over cells of (objects in the cell)^2): O(n + k) for objects about the
    // cell size (the grid's heuristic) with k pairs.
    std::vector<std::pair<iterator, iterator>> self_pairs(pair_filter filter = pair_filter::exact) const {
        std::vector<std::pair<iterator, iterator>> out;
        cells_.for_each_nonempty([&](const key& cell, const slot_list& list) {
            for (std::size_t i = 0; i < list.size(); ++i)
                for (std::size_t j = i + 1; j < list.size(); ++j) {
                    const O& a = slots_.value(list[i]);
                    const O& b = slots_.value(list[j]);
                    bool here = true;
                    for (std::size_t k = 0; k < D && here; ++k) {
                        const T lo = std::max(object_lower(a, k), object_lower(b, k));
                        const T hi = std::min(object_upper(a, k), object_upper(b, k));
                        here = !(hi < lo) && cell_of(lo, k) == cell[k];
                    }
                    if (!here) continue;
                    if (filter == pair_filter::exact && !collide::narrow_phase(a, b)) continue;
                    out.emplace_back(make(std::min(list[i], list[j])), make(std::max(list[i], list[j])));
                }
        });
        // A large object against every other object; a pair of two large ones once, from the
        // one in the lower slot. O(large objects x n).
        for (slot_index l : large_) {
            const O& a = slots_.value(l);
            for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) {
                if (s == l || (s < l && is_large_slot(s))) continue;
                const O& b = slots_.value(s);
                if (!object_boxes_overlap(a, b) || (filter == pair_filter::exact && !collide::narrow_phase(a, b))) continue;
                out.emplace_back(make(std::min(l, s)), make(std::max(l, s)));
            }
        }
        sort_pairs(out);
        return out;
    }
    // Bipartite: through this grid's box queries (pairs_between), O(|other| box queries).
    template <class Other>
    std::vector<std::pair<iterator, typename Other::iterator>> pairs_with(const Other& other,
                                                                         pair_filter filter = pair_filter::exact) const {
        return pairs_between(static_cast<const Derived&>(*this), other, filter);
    }

    std::size_t memory_bytes() const {
        return sizeof(Derived) + slots_.memory_bytes() + cells_.memory_bytes() + large_.capacity() * sizeof(slot_index);
    }
    // Objects kept in the list of large objects rather than in cells (see large_object_cells).
    std::size_t large_objects() const { return large_.size(); }
    // The cell edge (0 before the first insertion of a grid that chooses it from the data).
    scalar_type cell_size() const { return h_; }

    // Every object is listed in exactly the cells its box maps to, and nowhere else, or, if
    // it is large, once in the list of large objects and in no cell. O(n * cells + large^2).
    std::string check_invariants() const {
        std::size_t listed = 0, expected = 0;
        std::string err;
        for (slot_index l : large_)
            if (!slots_.occupied(l) || !is_large_slot(l))
                err = "the large objects list " + std::to_string(l) + ", erased or not large";
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) {
            const box Ro = range_of(extent_of(slots_.value(s)));
            if (is_large(Ro)) {
                if (std::count(large_.begin(), large_.end(), s) != 1) err = "large object " + std::to_string(s) + " not listed once";
                continue;
            }
            expected += static_cast<std::size_t>(Ro.count());
            for_each_cell(Ro, [&](const key& c) {
                const slot_list* list = cells_.find(c);
                if (!list || std::count(list->begin(), list->end(), s) != 1)
                    err = "object " + std::to_string(s) + " missing from one of its cells";
            });
        }
        cells_.for_each_nonempty([&](const key&, const slot_list& list) {
            listed += list.size();
            for (slot_index s : list)
                if (!slots_.occupied(s)) err = "a cell lists an erased object";
        });
        if (err.empty() && listed != expected)
            err = "cells list " + std::to_string(listed) + " entries, expected " + std::to_string(expected);
        return err;
    }

protected:
    grid_core() { reset_data_box(); }

    Derived& derived() { return static_cast<Derived&>(*this); }
    using contract_base::make;
    using contract_base::site;
    using contract_base::slots_;
    // The range-erase hooks of container_base: a range under a quarter is removed one by one
    // with a single re-grid check at the end; a larger one rebuilds the cells once, O(n).
    void erase_slots(std::span<const slot_index> doomed) {
        for (slot_index s : doomed) {
            remove_from_cells(s);
            slots_.release(s);
        }
        derived().after_erase();
    }
    void rebuild_survivors() { derived().rebuild(); }

    static extent extent_of(const O& x) {
        extent e;
        for (std::size_t i = 0; i < D; ++i) {
            e.lo[i] = object_lower(x, i);
            e.hi[i] = object_upper(x, i);
        }
        return e;
    }
    static void merge(extent& a, const extent& b) {
        for (std::size_t i = 0; i < D; ++i) {
            a.lo[i] = std::min(a.lo[i], b.lo[i]);
            a.hi[i] = std::max(a.hi[i], b.hi[i]);
        }
    }
    static double max_extent(const extent& e) {
        double m = 0;
        for (std::size_t i = 0; i < D; ++i) m = std::max(m, static_cast<double>(e.hi[i]) - static_cast<double>(e.lo[i]));
        return std::isfinite(m) ? m : 0;
    }

    // Monotone cell mapping, clamped to the storage's coordinate range.
    std::int64_t cell_of(T x, std::size_t i) const {
        const T f = std::floor((x - origin_[i]) / h_);
        const std::int64_t lo = cells_.clamp_lo(i), hi = cells_.clamp_hi(i);
        if (!(f > static_cast<T>(lo))) return lo;
        if (!(f < static_cast<T>(hi))) return hi;
        return static_cast<std::int64_t>(f);
    }
    box range_of(const extent& e) const {
        box b;
        for (std::size_t i = 0; i < D; ++i) {
            b.lo[i] = cell_of(e.lo[i], i);
            b.hi[i] = cell_of(e.hi[i], i);
        }
        return b;
    }

    // An object whose box maps to more cells than this (4^D: an object of up to about three
    // cells along every axis stays in its cells) is not listed in cells but kept in large_,
    // which every query tests: listing it would cost O(its cells) time and memory per
    // insertion and erasure (an unbounded hashed_grid allowed 2^24 cells) for one object a
    // query can test in O(1). A grid suits objects about its cell size (Ericson 2005,
    // "Real-Time Collision Detection", section 7.2); the few that are not (a floor, a wall,
    // an outlier thousands of cells long) cost each query one test instead.
    static constexpr double large_object_cells = cells_in_cube<D>(4);
    static bool is_large(const box& cells) { return cells.count() > large_object_cells; }
    // find_nearest goes on by blocks once its shells have walked more cells than two blocks
    // hold (far beyond what a query near the data walks: a few shells of cells), or at once
    // from an empty block, in a grid whose occupied cells span at least one block's worth.
    // (Until the blocks and cells of a shell were visited nearest first, the bar was 4^D
    // blocks' worth: blocks as wide as the clusters cost more than shells of cells, the
    // structures suite's clusters_far at 10^4 points was slower by blocks. Nearest first it is
    // faster there, and at 10^5.)
    static constexpr double block_walk_after = 2 * block_cells<D>;
    static constexpr double cells_worth_going_by_blocks = block_cells<D>;
    bool is_large_slot(slot_index s) const { return is_large(range_of(extent_of(slots_.value(s)))); }

    void add_to_cells(slot_index s) {
        const extent e = extent_of(slots_.value(s));
        const box r = range_of(e);
        if (is_large(r)) large_.push_back(s);
        else for_each_cell(r, [&](const key& c) { cells_.add(c, s); });
        for (std::size_t i = 0; i < D; ++i) {
            data_lo_[i] = std::min(data_lo_[i], e.lo[i]);
            data_hi_[i] = std::max(data_hi_[i], e.hi[i]);
        }
    }
    // Lists stored slots (boxes within `all`) in their cells, grouped by cell.
    void list_batch(const std::vector<std::pair<slot_index, bool>>& stored, const extent& all) {
        std::vector<cell_entry<D>> entries;
        if constexpr (bounded_object<O>) {
            double cells = 0;
            for (const auto& st : stored) {
                const double c = range_of(extent_of(slots_.value(st.first))).count();
                if (c <= large_object_cells) cells += c;
            }
            entries.reserve(static_cast<std::size_t>(cells));
            for (const auto& st : stored) {
                const box r = range_of(extent_of(slots_.value(st.first)));
                if (is_large(r)) large_.push_back(st.first);
                else for_each_cell(r, [&](const key& c) { entries.push_back({c, st.first}); });
            }
        } else {
            entries.reserve(stored.size());
            for (const auto& st : stored) {
                const O& x = slots_.value(st.first);
                key c;
                for (std::size_t i = 0; i < D; ++i) c[i] = cell_of(x[i], i);
                entries.push_back({c, st.first});
            }
        }
        cells_.add_batch(entries);
        for (std::size_t i = 0; i < D; ++i) {
            data_lo_[i] = std::min(data_lo_[i], all.lo[i]);
            data_hi_[i] = std::max(data_hi_[i], all.hi[i]);
        }
    }
    // Does not allocate (a failed insertion's undo relies on it): a slot that no cell or list
    // holds yet is skipped.
    void remove_from_cells(slot_index s) {
        const box r = range_of(extent_of(slots_.value(s)));
        if (is_large(r)) {
            const auto it = std::find(large_.begin(), large_.end(), s);
            if (it != large_.end()) large_.erase(it);
            return;
        }
        for_each_cell(r, [&](const key& c) { cells_.remove(c, s); });
    }
    // Re-lists every live object (after the storage was reset).
    void refill_cells() {
        large_.clear();
        reset_data_box();
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
            add_to_cells(s);
    }
    void reset_data_box() {
        data_lo_.fill(std::numeric_limits<T>::infinity());
        data_hi_.fill(-std::numeric_limits<T>::infinity());
    }
    // What a re-grid sets aside before it lists the objects afresh (refill_cells), and puts
    // back if that fails (strong guarantee): moves only, no allocation.
    struct listing {
        Cells cells;
        std::vector<slot_index> large;
        coords data_lo, data_hi;
    };
    listing set_aside_listing() {
        return listing{std::move(cells_), std::move(large_), data_lo_, data_hi_};
    }
    void restore_listing(listing& old) noexcept {
        cells_ = std::move(old.cells);
        large_ = std::move(old.large);
        data_lo_ = old.data_lo;
        data_hi_ = old.data_hi;
    }

    // Bounding box and mean size of the live objects plus an optional extra box (count m,
    // extent sum es): the input of the cell-size heuristic.
    void data_statistics(const extent* extra, std::size_t m, double es, extent& box_out, double& mean_extent,
                         double& n) const {
        bool any = extra != nullptr;
        if (extra) box_out = *extra;
        double sum = es;
        for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1)) {
            const extent e = extent_of(slots_.value(s));
            if (!any) box_out = e;
            any = true;
            merge(box_out, e);
            sum += max_extent(e);
        }
        n = static_cast<double>(slots_.size() + m);
        mean_extent = n > 0 ? sum / n : 0;
    }

    Cells cells_;
    std::vector<slot_index> large_;  // the large objects (large_object_cells), listed in no cell
    coords origin_{};
    T h_ = 0;
    coords data_lo_{}, data_hi_{};  // box of everything listed since the last refill (grow-only)

private:
    iterator insert_one(const O& x, detail::call_site where) {
        require_finite_object(x, where);
        const extent e = extent_of(x);
        derived().prepare_insert(e, 1, max_extent(e));
        return make(store(x));
    }
    // Stores x in a slot and lists it in its cells; if a cell list cannot grow, x is taken out
    // of the cells it reached and its slot given back (strong guarantee).
    slot_index store(const O& x) {
        const bool reused = slots_.reuses_a_slot();
        const slot_index s = slots_.allocate(x, 0);
        try {
            add_to_cells(s);
        } catch (const std::bad_alloc&) {
            remove_from_cells(s);  // a cell it did not reach does not list it: nothing to do there
            slots_.undo_allocate(s, reused);
            throw;
        }
        return s;
    }

    void collect_equal(const O& x, std::vector<slot_index>& out, bool first_only) const {
        if (slots_.size() == 0 || !(h_ > 0)) return;
        const box Rx = range_of(extent_of(x));
        std::span<const slot_index> list;
        if (is_large(Rx)) list = large_;
        else if (const slot_list* cell = cells_.find(Rx.lo)) list = {cell->begin(), cell->size()};
        for (slot_index s : list)
            if (slots_.value(s) == x) {
                out.push_back(s);
                if (first_only) return;
            }
    }

    static bool is_first_cell(const box& Ro, const box& Q, const key& cell) {
        for (std::size_t i = 0; i < D; ++i)
            if (std::max(Ro.lo[i], Q.lo[i]) != cell[i]) return false;
        return true;
    }
    // Chebyshev distance from cell a to the nearest cell of box R.
    static std::int64_t chebyshev_to_range(const key& a, const box& R) {
        std::int64_t m = 0;
        for (std::size_t i = 0; i < D; ++i) m = std::max({m, R.lo[i] - a[i], a[i] - R.hi[i]});
        return m;
    }
    static std::int64_t chebyshev(const key& a, const key& b) {
        std::int64_t m = 0;
        for (std::size_t i = 0; i < D; ++i) m = std::max(m, a[i] > b[i] ? a[i] - b[i] : b[i] - a[i]);
        return m;
    }

    // Calls f(slot) once per large object and once per object listed in the cells of Q
    // (clipped to the occupied box), each at its canonical cell; scans the occupied cells when
    // Q is larger. f tests the object exactly.
    template <class F>
    void for_each_in_query(box Q, F&& f) const {
        for (slot_index s : large_) f(s);
        Q = Q.clipped(cells_.bounds());
        if (Q.empty()) return;
        auto visit = [&](const key& cell, const slot_list& list) {
            for (slot_index s : list) {
                if constexpr (bounded_object<O>) {
                    if (!is_first_cell(range_of(extent_of(slots_.value(s))), Q, cell)) continue;
                }
                f(s);
            }
        };
        const double objects = static_cast<double>(slots_.size());
        if (Q.count() > std::min(cells_.occupied_cells(), objects) + 8) {
            if (objects < cells_.occupied_cells()) {  // objects span many cells: test each once
                for (slot_index s = slots_.next_occupied(0); s < slots_.capacity(); s = slots_.next_occupied(s + 1))
                    if (!is_large_slot(s)) f(s);
                return;
            }
            cells_.for_each_nonempty([&](const key& cell, const slot_list& list) {
                if (Q.contains(cell)) visit(cell, list);
            });
            return;
        }
        for_each_cell(Q, [&](const key& cell) {
            if (const slot_list* list = cells_.find(cell)) visit(cell, *list);
        });
    }

    // Cells at Chebyshev distance exactly r from cq, within R.
    static double ring_count(const key& cq, std::int64_t r, const box& R) {
        box outer, inner;
        for (std::size_t i = 0; i < D; ++i) {
            outer.lo[i] = cq[i] - r;
            outer.hi[i] = cq[i] + r;
            inner.lo[i] = cq[i] - r + 1;
            inner.hi[i] = cq[i] + r - 1;
        }
        return outer.clipped(R).count() - (r > 0 ? inner.clipped(R).count() : 0.0);
    }
    template <class F>
    static void for_each_ring_cell(const key& cq, std::int64_t r, const box& R, F&& f) {
        key c{};
        ring_axis(D - 1, false, cq, r, R, c, f);
    }
    template <class F>
    static void ring_axis(std::size_t i, bool on_shell, const key& cq, std::int64_t r, const box& R, key& c, F& f) {
        const std::int64_t lo = std::max(cq[i] - r, R.lo[i]), hi = std::min(cq[i] + r, R.hi[i]);
        if (lo > hi) return;
        if (i == 0 && !on_shell) {  // only the two faces of the last axis are on the shell
            const std::int64_t a = cq[0] - r, b = cq[0] + r;
            if (a >= lo && a <= hi) {
                c[0] = a;
                f(static_cast<const key&>(c));
            }
            if (b != a && b >= lo && b <= hi) {
                c[0] = b;
                f(static_cast<const key&>(c));
            }
            return;
        }
        for (std::int64_t v = lo; v <= hi; ++v) {
            c[i] = v;
            const bool on = on_shell || v == cq[i] - r || v == cq[i] + r;
            if (i == 0) f(static_cast<const key&>(c));
            else ring_axis(i - 1, on, cq, r, R, c, f);
        }
    }

    // The rounding of a cell face's coordinate on axis i (origin + j h) and of the cell
    // mapping, relative to x: what the distance bounds below subtract.
    T face_slack(const point_type& x, std::size_t i, T face) const {
        return 8 * std::numeric_limits<T>::epsilon() * (std::abs(x[i]) + std::abs(origin_[i]) + std::abs(face));
    }
    // Lower bound on the squared distance from x to anything that meets a cell of the box
    // `cells` only (an object whose canonical cell is in it lies in the box of its cell range,
    // which is no nearer on any axis). Widened as shell_lower_bound's faces are. A hashed
    // grid's cells at the clamp of the cell coordinates also hold every object beyond it, so
    // a box reaching the clamp has no face on that side (fuzzing found the bound of such a
    // cell, from its nominal faces, pruning the nearest object at 1e30: docs/fuzzing.md).
    T cells_squared_lower_bound(const point_type& x, const box& cells) const {
        T sum = 0;
        for (std::size_t i = 0; i < D; ++i) {
            const bool open_below = Cells::clamp_cells_hold_beyond && cells.lo[i] <= cells_.clamp_lo(i);
            const bool open_above = Cells::clamp_cells_hold_beyond && cells.hi[i] >= cells_.clamp_hi(i);
            const T lo = origin_[i] + static_cast<T>(cells.lo[i]) * h_;
            const T hi = origin_[i] + static_cast<T>(cells.hi[i] + 1) * h_;
            T gap = 0;
            if (x[i] < lo && !open_below) gap = lo - x[i] - face_slack(x, i, lo);
            else if (x[i] > hi && !open_above) gap = x[i] - hi - face_slack(x, i, hi);
            gap = std::max(gap, T(0));
            sum += gap * gap;
        }
        return sum;
    }
    // Lower bound on the distance from x to any object none of whose cells lies within
    // Chebyshev distance r of cq: such an object lies entirely beyond a face of the shell's
    // box on some axis (only faces with occupied cells beyond them count). Widened by the
    // rounding of the cell mapping and of the face coordinates. +inf when no face remains.
    T shell_lower_bound(const point_type& x, const key& cq, std::int64_t r, const box& R) const {
        T lb = std::numeric_limits<T>::infinity();
        for (std::size_t i = 0; i < D; ++i) {
            if (cq[i] + r < R.hi[i]) {
                const T face = origin_[i] + static_cast<T>(cq[i] + r + 1) * h_;
                lb = std::min(lb, face - x[i] - face_slack(x, i, face));
            }
            if (cq[i] - r > R.lo[i]) {
                const T face = origin_[i] + static_cast<T>(cq[i] - r) * h_;
                lb = std::min(lb, x[i] - face - face_slack(x, i, face));
            }
        }
        return std::max(lb, T(0));
    }
};

}  // namespace spatial::detail
