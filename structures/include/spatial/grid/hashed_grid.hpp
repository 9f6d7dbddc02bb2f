#pragma once
// spatial::hashed_grid<O, Config> — an unbounded grid of fixed cell size whose non-empty
// cells live in a hash map keyed by integer cell coordinates (Teschner, Heidelberger, Mueller,
// Pomeranets & Gross 2003, "Optimized spatial hashing for collision detection of deformable
// objects"). Memory is O(occupied cells), independent of the scene's extent, so sparse and
// unbounded scenes (a few far outliers, an open world) cost nothing extra; it never re-grids.
//
// Cell size: the constructor argument, else chosen ONCE by the first insertion — a bulk
// insert uses the uniform grid's heuristic over the batch (choose_cell_size in grid_core.hpp),
// a single insert uses the larger of the object's largest extent and 1/16 of its largest
// coordinate magnitude (1 at the origin). Pass a size when the scale is known. clear() keeps
// the size. Cell coordinates are floor(x / h) clamped to +-2^50.
//
// Costs: insert/erase O(cells an object overlaps) expected (hash operations). An object
// spanning more than 4^D cells is kept in a list of large objects that every query tests
// (grid_core.hpp, large_object_cells), so no object costs more than O(4^D) cells. Queries as in
// grid_core.hpp; the DDA and the kNN shells walk empty cells too, and fall back to a scan of the
// occupied cells when that is cheaper, so no query exceeds O(occupied cells + n).

#include <new>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "spatial/core/container_concept.hpp"
#include "spatial/core/input_checks.hpp"
#include "spatial/grid/cell_storage.hpp"
#include "spatial/grid/grid_core.hpp"

namespace spatial {

template <unsigned ObjectsPerCell = 2>
struct hashed_grid_config {
    // Used only when the first bulk insert chooses the cell size.
    static constexpr double objects_per_cell = ObjectsPerCell;
};

template <stored_object O, class Config = hashed_grid_config<>>
class hashed_grid
    : public detail::grid_core<O, detail::hashed_cells<O::dimension>, hashed_grid<O, Config>> {
    using base = detail::grid_core<O, detail::hashed_cells<O::dimension>, hashed_grid<O, Config>>;
    friend base;
    using typename base::extent;
    using typename base::T;
    using base::D;

public:
    using config = Config;
    static constexpr const char* structure_name = "hashed_grid";

    // Cell size chosen by the first insertion.
    hashed_grid() = default;
    // A fixed cell size (finite, > 0).
    explicit hashed_grid(typename base::scalar_type cell_size) {
        if (!(cell_size > 0) || !std::isfinite(cell_size))
            throw std::invalid_argument("hashed_grid: cell size must be finite and > 0, got " +
                                        std::to_string(static_cast<double>(cell_size)));
        this->h_ = cell_size;
    }
    template <class InputIt>
    hashed_grid(InputIt first, InputIt last) { this->insert(first, last); }
    hashed_grid(const hashed_grid&) = default;
    hashed_grid& operator=(const hashed_grid&) = default;
    // A moved-from grid is empty (and keeps no cell size).
    hashed_grid(hashed_grid&& o) noexcept : base(std::move(static_cast<base&>(o))) {
        o.clear();
        o.h_ = 0;
    }
    hashed_grid& operator=(hashed_grid&& o) noexcept {
        if (this != &o) {
            base::operator=(std::move(static_cast<base&>(o)));
            o.clear();
            o.h_ = 0;
        }
        return *this;
    }

    // Non-empty cells.
    std::size_t occupied_cells() const { return static_cast<std::size_t>(this->cells_.occupied_cells()); }

private:
    void prepare_insert(const extent& batch_box, std::size_t m, double extent_sum) {
        if (this->h_ > 0) return;
        if (m > 1) {
            this->h_ = detail::choose_cell_size<T, D>(batch_box.lo, batch_box.hi, static_cast<double>(m),
                                                      extent_sum / static_cast<double>(m), Config::objects_per_cell);
            this->cells_.reserve(m);
            return;
        }
        T size = 0, magnitude = 0;
        for (std::size_t i = 0; i < D; ++i) {
            size = std::max(size, batch_box.hi[i] - batch_box.lo[i]);
            magnitude = std::max({magnitude, std::abs(batch_box.lo[i]), std::abs(batch_box.hi[i])});
        }
        // No scale information but one object: its size, and at least 1/16 of its distance
        // from the origin (a scene around x spans about |x|), 1 at the origin.
        if (!std::isfinite(size)) size = 0;
        size = std::max(size, magnitude / 16);
        if (!(size > 0)) size = T(1);
        this->h_ = std::max(size, std::numeric_limits<T>::min() * 1024);
    }
    void after_erase() {}
    // Strong guarantee: the old cells are set aside and put back if the new ones cannot be
    // filled.
    void rebuild() {
        auto old = this->set_aside_listing();
        try {
            this->cells_.clear();
            this->refill_cells();
        } catch (const std::bad_alloc&) {
            this->restore_listing(old);
            throw;
        }
    }
    void reset_cells() { this->cells_.clear(); }
};

}  // namespace spatial

#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"
static_assert(spatial::spatial_container<spatial::hashed_grid<spatial::point<double, 3>>>);
static_assert(spatial::spatial_container<spatial::hashed_grid<spatial::point<float, 2>>>);
static_assert(spatial::spatial_container<spatial::hashed_grid<spatial::objects::box<double, 3>>>);
