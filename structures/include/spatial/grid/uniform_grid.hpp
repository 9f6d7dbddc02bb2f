#pragma once
// spatial::uniform_grid<O, Config> — a dense uniform grid over the bounding box of the data
// (Cleary 1979 for the idea of analysing/traversing a regular cell decomposition; ray casting by
// the 3D-DDA of Amanatides & Woo 1987). Objects with extent are listed in every cell they
// overlap; queries never report one twice (grid_core.hpp explains how, without marks).
//
// Cell size heuristic (choose_cell_size in grid_core.hpp): about n / objects_per_cell cells
// over the box, h = (box volume / cells)^(1/D) over the axes of positive extent, bounded below
// by the mean object extent (so an object overlaps O(2^D) cells) and by 64 ulps of the
// coordinates, and enlarged until the array has at most 4 n / objects_per_cell + 64 cells.
// The box is the data's bounding box widened by 1/8 of its extent on each side, so a stream
// drifting outward re-grids a logarithmic number of times.
//
// Re-gridding (O(n), slots and iterators survive it): when an inserted object leaves the box,
// when the count exceeds 2 x (count at the last re-grid) + 16, or when erasures bring it below a
// quarter of it (only once it was >= 64). Each re-grid is paid for by the Omega(n) insertions or
// erasures since the previous one, so insertion and erasure are amortised O(1) (times the
// cells an object overlaps). Weakness (documented, measured): data with a few far outliers
// get huge cells; use hashed_grid or a tree for such scenes.

#include <new>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "spatial/core/container_concept.hpp"
#include "spatial/grid/cell_storage.hpp"
#include "spatial/grid/grid_core.hpp"

namespace spatial {

template <unsigned ObjectsPerCell = 2>
struct uniform_grid_config {
    // Target mean number of objects per cell; 2 balances the empty cells a query steps
    // through against the objects it tests per cell.
    static constexpr double objects_per_cell = ObjectsPerCell;
};

template <stored_object O, class Config = uniform_grid_config<>>
class uniform_grid
    : public detail::grid_core<O, detail::dense_cells<O::dimension>, uniform_grid<O, Config>> {
    using base = detail::grid_core<O, detail::dense_cells<O::dimension>, uniform_grid<O, Config>>;
    friend base;
    using typename base::extent;
    using typename base::T;
    using base::D;

public:
    using config = Config;
    static constexpr const char* structure_name = "uniform_grid";

    uniform_grid() = default;
    template <class InputIt>
    uniform_grid(InputIt first, InputIt last) { this->insert(first, last); }
    // Copies are independent; a moved-from grid is empty.
    uniform_grid(const uniform_grid&) = default;
    uniform_grid& operator=(const uniform_grid&) = default;
    uniform_grid(uniform_grid&& o) noexcept
        : base(std::move(static_cast<base&>(o))), built_(o.built_), size_at_grid_(o.size_at_grid_),
          regrids_(o.regrids_), box_lo_(o.box_lo_), box_hi_(o.box_hi_) {
        o.clear();
    }
    uniform_grid& operator=(uniform_grid&& o) noexcept {
        if (this != &o) {
            base::operator=(std::move(static_cast<base&>(o)));
            built_ = o.built_;
            size_at_grid_ = o.size_at_grid_;
            regrids_ = o.regrids_;
            box_lo_ = o.box_lo_;
            box_hi_ = o.box_hi_;
            o.clear();
        }
        return *this;
    }

    // Cells per axis of the current grid.
    const detail::cell_key<D>& grid_dims() const { return this->cells_.dims(); }
    // How many times the grid was chosen afresh (tests: amortisation).
    std::size_t regrid_count() const { return regrids_; }

private:
    // Before m objects with bounding box `box` are stored: re-grid if they leave the box or
    // the count outgrew the grid. Returns nothing; afterwards the grid covers `box`.
    void prepare_insert(const extent& batch_box, std::size_t m, double extent_sum) {
        const bool outgrown = this->slots_.size() + m > 2 * size_at_grid_ + 16;
        if (!built_ || outgrown || !inside(batch_box)) regrid(&batch_box, m, extent_sum);
    }
    void after_erase() {
        if (this->slots_.size() == 0) {
            reset_cells();
            this->reset_data_box();
        } else if (size_at_grid_ >= 64 && this->slots_.size() * 4 < size_at_grid_) {
            // Shrinking is best-effort: without memory for the smaller grid, the erase still
            // succeeds and the old grid (still correct, only sparser) stays until the next one.
            try {
                regrid(nullptr, 0, 0);
            } catch (const std::bad_alloc&) {
            }
        }
    }
    void rebuild() {
        if (this->slots_.size() == 0) {
            reset_cells();
            this->reset_data_box();
        } else {
            regrid(nullptr, 0, 0);
        }
    }
    void reset_cells() {
        this->cells_.clear();
        built_ = false;
        size_at_grid_ = 0;
    }

    bool inside(const extent& e) const {
        for (std::size_t i = 0; i < D; ++i)
            if (e.lo[i] < box_lo_[i] || e.hi[i] > box_hi_[i]) return false;
        return true;
    }

    void regrid(const extent* extra, std::size_t m, double extent_sum) {
        extent bb{};
        double mean = 0, n = 0;
        this->data_statistics(extra, m, extent_sum, bb, mean, n);
        for (std::size_t i = 0; i < D; ++i) {  // margin: 1/8 of the extent per side
            const T margin = (bb.hi[i] - bb.lo[i]) / 8;
            if (std::isfinite(margin)) {
                bb.lo[i] -= margin;
                bb.hi[i] += margin;
            }
        }
        const T h = detail::choose_cell_size<T, D>(bb.lo, bb.hi, n, mean, Config::objects_per_cell);
        detail::cell_key<D> dims;
        for (std::size_t i = 0; i < D; ++i) {
            const double cells = std::ceil((static_cast<double>(bb.hi[i]) - static_cast<double>(bb.lo[i])) / static_cast<double>(h));
            dims[i] = static_cast<std::int64_t>(std::clamp(cells, 1.0, 1e9));
        }
        // Strong guarantee: the old grid is set aside, and put back if the new one cannot be
        // filled (moves and swaps of the cells do not allocate).
        auto old = this->set_aside_listing();
        const auto old_origin = this->origin_;
        const T old_h = this->h_;
        try {
            this->origin_ = bb.lo;
            this->h_ = h;
            this->cells_.reset(dims);
            this->refill_cells();
        } catch (const std::bad_alloc&) {
            this->restore_listing(old);
            this->origin_ = old_origin, this->h_ = old_h;
            throw;
        }
        box_lo_ = bb.lo;
        box_hi_ = bb.hi;
        built_ = true;
        size_at_grid_ = static_cast<std::size_t>(n);
        ++regrids_;
    }

    bool built_ = false;
    std::size_t size_at_grid_ = 0;
    std::size_t regrids_ = 0;
    typename base::coords box_lo_{}, box_hi_{};
};

}  // namespace spatial

#include "spatial/core/point.hpp"
#include "spatial/objects/box.hpp"
static_assert(spatial::spatial_container<spatial::uniform_grid<spatial::point<double, 3>>>);
static_assert(spatial::spatial_container<spatial::uniform_grid<spatial::point<float, 2>>>);
static_assert(spatial::spatial_container<spatial::uniform_grid<spatial::objects::box<double, 3>>>);
