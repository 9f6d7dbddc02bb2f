#pragma once
// Blocks of cells: the coarse level a grid keeps beside its cells so that a k-nearest search
// far from the data can skip empty space a block at a time (grid_core.hpp, find_nearest).
//
// A block is block_edge<D>^D cells, aligned on multiples of block_edge (8 for D <= 3, so 512
// cells in 3D; 4 above, where 8^D cells would be too coarse). Each storage (cell_storage.hpp)
// keeps per block which of its cells are non-empty (a count and a bit mask in the dense one,
// a list of cells in the hashed one), up to date where a cell becomes non-empty or empty:
// O(1) per such change. Without it a query in empty space walked every cell of every
// shell up to the nearest object: on 10^7 clustered points (cells of about two points) a
// query between the clusters visited millions of cells, about O(n) per query. A coarse level
// is the idea of the hierarchical grids of Ericson, "Real-Time Collision Detection" (2005),
// §7.2, and of the occupancy pyramids of sparse voxel grids; here it is one level, read only
// by the kNN search once its walk of single cells has grown past a few blocks.

#include <cstddef>
#include <cstdint>

#include "spatial/grid/cell_box.hpp"

namespace spatial::detail {

// log2 of the block edge, in cells.
template <std::size_t D>
inline constexpr unsigned block_shift = D <= 3 ? 3u : 2u;
template <std::size_t D>
inline constexpr std::int64_t block_edge = std::int64_t(1) << block_shift<D>;
template <std::size_t D>
inline constexpr double block_cells = cells_in_cube<D>(static_cast<double>(block_edge<D>));

// A cell's position inside its block, 0 .. block_cells - 1: its low block_shift bits per axis,
// axis 0 lowest (the index of its bit in a block's mask of non-empty cells).
template <std::size_t D>
std::size_t cell_in_block(const cell_key<D>& c) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < D; ++i)
        n |= static_cast<std::size_t>(c[i] & (block_edge<D> - 1)) << (block_shift<D> * i);
    return n;
}
// The cell at position n of block b (the inverse of cell_in_block).
template <std::size_t D>
cell_key<D> cell_of_block(const cell_key<D>& b, std::size_t n) {
    cell_key<D> c;
    for (std::size_t i = 0; i < D; ++i)
        c[i] = b[i] * block_edge<D> + static_cast<std::int64_t>((n >> (block_shift<D> * i)) & (block_edge<D> - 1));
    return c;
}

// The block holding cell c: floor(c / block_edge) per axis (an arithmetic shift, so negative
// cell coordinates of a hashed grid round down as well).
template <std::size_t D>
cell_key<D> block_of(const cell_key<D>& c) {
    cell_key<D> b;
    for (std::size_t i = 0; i < D; ++i) b[i] = c[i] >> block_shift<D>;
    return b;
}
// The cells of block b.
template <std::size_t D>
cell_box<D> cells_of_block(const cell_key<D>& b) {
    cell_box<D> r;
    for (std::size_t i = 0; i < D; ++i) {
        r.lo[i] = b[i] * block_edge<D>;
        r.hi[i] = r.lo[i] + block_edge<D> - 1;
    }
    return r;
}
// The blocks overlapping a box of cells.
template <std::size_t D>
cell_box<D> blocks_of(const cell_box<D>& cells) {
    cell_box<D> r;
    for (std::size_t i = 0; i < D; ++i) {
        r.lo[i] = cells.lo[i] >> block_shift<D>;
        r.hi[i] = cells.hi[i] >> block_shift<D>;
    }
    return r;
}

}  // namespace spatial::detail
