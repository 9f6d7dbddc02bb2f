#pragma once
// The two ways a grid stores its cells' slot lists, behind one small interface used by
// grid_core.hpp:
//  * dense_cells  — a flat array over a box of dims[0] x ... x dims[D-1] cells (uniform_grid);
//  * hashed_cells — a hash map keyed by the integer cell coordinates, holding only non-empty
//    cells (hashed_grid; Teschner et al. 2003, "Optimized spatial hashing for collision
//    detection of deformable objects": hash = (x p1 xor y p2 xor z p3) with large primes).
// Both expose: the clamp range of cell coordinates (the cell mapping clamps to it, which keeps
// it monotone), the box of cells that may be non-empty, lookup, insertion and removal of a
// slot in a cell, and iteration over the non-empty cells (the fallback of queries whose cell
// box would be larger than the set of occupied cells); add_batch, which lists a whole
// batch of (cell, slot) entries grouped by cell: one lookup and one reservation per cell
// instead of one per entry (bulk insertion); and per block of cells (cell_blocks.hpp) whether
// any of its cells is non-empty and which, kept where a cell becomes non-empty or empty.

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "spatial/core/radix_sort.hpp"
#include "spatial/core/reserve_for_push.hpp"
#include "spatial/core/slot_storage.hpp"
#include "spatial/grid/cell_blocks.hpp"
#include "spatial/grid/cell_box.hpp"
#include "spatial/grid/slot_list.hpp"

namespace spatial::detail {

// One (cell, slot) listing of a bulk insertion; `order` is the storage's sort key for it.
template <std::size_t D>
struct cell_entry {
    cell_key<D> cell;
    slot_index slot;
    std::uint32_t order = 0;
};

// Calls f(first, last) for each run of entries with equal `order` in a sorted range.
template <class Entry, class F>
void for_each_run(std::vector<Entry>& v, F&& f) {
    for (std::size_t a = 0; a < v.size();) {
        std::size_t b = a + 1;
        while (b < v.size() && v[b].order == v[a].order) ++b;
        f(a, b);
        a = b;
    }
}

template <std::size_t D>
class dense_cells {
public:
    using key = cell_key<D>;
    // A dims[0] x ... x dims[D-1] array of empty cells (dims >= 1 each).
    void reset(const key& dims) {
        dims_ = dims;
        std::size_t n = 1;
        for (std::size_t i = 0; i < D; ++i) {
            stride_[i] = n;
            n *= static_cast<std::size_t>(dims[i]);
        }
        cells_.assign(n, {});
        std::size_t blocks = 1;
        for (std::size_t i = 0; i < D; ++i) {
            block_dims_[i] = ((dims[i] - 1) >> block_shift<D>) + 1;
            block_stride_[i] = blocks;
            blocks *= static_cast<std::size_t>(block_dims_[i]);
        }
        block_cells_.assign(blocks, 0);
        block_masks_.assign(blocks * mask_words, 0);
    }
    void clear() {
        cells_.clear();
        cells_.shrink_to_fit();
        block_cells_.clear();
        block_cells_.shrink_to_fit();
        block_masks_.clear();
        block_masks_.shrink_to_fit();
        dims_.fill(0);
        block_dims_.fill(0);
    }
    std::int64_t clamp_lo(std::size_t) const { return 0; }
    std::int64_t clamp_hi(std::size_t i) const { return dims_[i] - 1; }
    // The uniform grid re-grids so that every object lies in its box: the clamp only ever
    // moves a query point, and each cell holds objects within its own faces.
    static constexpr bool clamp_cells_hold_beyond = false;
    cell_box<D> bounds() const {
        cell_box<D> b;
        for (std::size_t i = 0; i < D; ++i) b.hi[i] = dims_[i] - 1;
        return b;
    }
    const slot_list* find(const key& k) const {
        for (std::size_t i = 0; i < D; ++i)
            if (k[i] < 0 || k[i] >= dims_[i]) return nullptr;
        return &cells_[index(k)];
    }
    void add(const key& k, slot_index s) {
        slot_list& list = cells_[index(k)];
        list.push_back(s);
        if (list.size() == 1) mark(k, true);
    }
    void remove(const key& k, slot_index s) {
        slot_list& list = cells_[index(k)];
        if (list.empty()) return;
        list.remove(s);
        if (list.empty()) mark(k, false);
    }
    // Whether any cell of block b is non-empty (false outside the array).
    bool block_occupied(const key& b) const {
        for (std::size_t i = 0; i < D; ++i)
            if (b[i] < 0 || b[i] >= block_dims_[i]) return false;
        return block_cells_[block_index(b)] != 0;
    }
    // As occupied_cells(): the array's blocks, a bound on those a query may find occupied.
    double occupied_blocks() const { return static_cast<double>(block_cells_.size()); }
    // f(b) for each block holding a non-empty cell.
    template <class F>
    void for_each_occupied_block(F&& f) const {
        for_each_cell(blocks_of(bounds()), [&](const key& b) {
            if (block_cells_[block_index(b)] != 0) f(b);
        });
    }
    // f(cell, list) for each non-empty cell of block b (inside the array): through the block's
    // mask, O(block cells / 64 + its non-empty cells). Reading the block's 512 cells instead
    // (3D) touched 12 KiB a block and was half of a far query's time.
    template <class F>
    void for_each_nonempty_in_block(const key& b, F&& f) const {
        const std::uint64_t* words = &block_masks_[block_index(b) * mask_words];
        for (std::size_t w = 0; w < mask_words; ++w)
            for (std::uint64_t bits = words[w]; bits != 0; bits &= bits - 1) {
                const key cell = cell_of_block(b, w * 64 + static_cast<std::size_t>(std::countr_zero(bits)));
                f(cell, cells_[index(cell)]);
            }
    }
    // Counting sort by cell index (radix_sort.hpp), then one reservation per cell and the
    // lists filled in cell order (sequential in the cell array). If a reservation fails, the
    // cells before it list their entries and the rest do not (grid_core undoes the batch).
    void add_batch(std::vector<cell_entry<D>>& entries) {
        if (cells_.size() <= (std::size_t(1) << 32)) {
            for (auto& e : entries) e.order = static_cast<std::uint32_t>(index(e.cell));
            radix_sort_by_order(entries, bits_below(cells_.size()));
            for_each_run(entries, [&](std::size_t a, std::size_t b) {
                auto& list = cells_[entries[a].order];
                reserve_for_push(list, b - a);
                const bool was_empty = list.empty();
                for (std::size_t i = a; i < b; ++i) list.push_back(entries[i].slot);
                if (was_empty) mark(entries[a].cell, true);
            });
        } else {  // more than 2^32 cells: beyond a 32-bit key, list them one by one
            for (const auto& e : entries) add(e.cell, e.slot);
        }
    }
    double occupied_cells() const { return static_cast<double>(cells_.size()); }
    template <class F>
    void for_each_nonempty(F&& f) const {
        for (std::size_t n = 0; n < cells_.size(); ++n) {
            if (cells_[n].empty()) continue;
            key k;
            std::size_t r = n;
            for (std::size_t i = 0; i < D; ++i) {
                k[i] = static_cast<std::int64_t>(r % static_cast<std::size_t>(dims_[i]));
                r /= static_cast<std::size_t>(dims_[i]);
            }
            f(k, cells_[n]);
        }
    }
    std::size_t memory_bytes() const {
        std::size_t b = cells_.capacity() * sizeof(slot_list) + block_cells_.capacity() * sizeof(std::uint32_t) +
                        block_masks_.capacity() * sizeof(std::uint64_t);
        for (const auto& c : cells_) b += c.heap_bytes();
        return b;
    }
    const key& dims() const { return dims_; }

private:
    std::size_t index(const key& k) const {
        std::size_t n = 0;
        for (std::size_t i = 0; i < D; ++i) n += static_cast<std::size_t>(k[i]) * stride_[i];
        return n;
    }
    std::size_t block_index(const key& b) const {
        std::size_t n = 0;
        for (std::size_t i = 0; i < D; ++i) n += static_cast<std::size_t>(b[i]) * block_stride_[i];
        return n;
    }
    // Cell k has become non-empty (true) or empty: its block's count and mask bit.
    void mark(const key& k, bool nonempty) {
        const std::size_t b = block_index(block_of(k)), n = cell_in_block(k);
        std::uint64_t& word = block_masks_[b * mask_words + n / 64];
        const std::uint64_t bit = std::uint64_t(1) << (n % 64);
        if (nonempty) {
            ++block_cells_[b];
            word |= bit;
        } else {
            --block_cells_[b];
            word &= ~bit;
        }
    }
    static constexpr std::size_t mask_words = (static_cast<std::size_t>(block_cells<D>) + 63) / 64;
    key dims_{}, block_dims_{};
    std::array<std::size_t, D> stride_{}, block_stride_{};
    std::vector<slot_list> cells_;
    std::vector<std::uint32_t> block_cells_;   // per block: its non-empty cells
    std::vector<std::uint64_t> block_masks_;   // per block, mask_words words: bit cell_in_block set if non-empty
};

// Teschner et al.'s hash over D integer coordinates, followed by a multiplicative finaliser
// (the plain xor of products maps small neighbouring coordinates to nearby values, which
// suits a prime-sized table but not a power-of-two one).
template <std::size_t D>
struct teschner_hash {
    std::size_t operator()(const cell_key<D>& k) const noexcept {
        static constexpr std::uint64_t primes[8] = {73856093ULL,  19349663ULL,  83492791ULL,  2654435761ULL,
                                                    2246822519ULL, 3266489917ULL, 668265263ULL, 374761393ULL};
        std::uint64_t h = 0;
        for (std::size_t i = 0; i < D; ++i) h ^= static_cast<std::uint64_t>(k[i]) * primes[i % 8];
        h ^= h >> 31;
        h *= 0x9E3779B97F4A7C15ULL;
        h ^= h >> 29;
        return static_cast<std::size_t>(h);
    }
};

template <std::size_t D>
class hashed_cells {
public:
    using key = cell_key<D>;
    // Cell coordinates are clamped to +-2^50 (far beyond any useful grid; keeps every
    // coordinate and difference exact in int64 and in double).
    static constexpr std::int64_t limit = std::int64_t(1) << 50;

    hashed_cells() = default;
    // The blocks point into the map's nodes: a copy links its own.
    hashed_cells(const hashed_cells& o) : map_(o.map_), bounds_(o.bounds_) { link_blocks(); }
    hashed_cells& operator=(const hashed_cells& o) {
        if (this != &o) *this = hashed_cells(o);
        return *this;
    }
    // Moving a node-based map keeps its nodes where they are, so the pointers stay valid.
    hashed_cells(hashed_cells&&) = default;
    hashed_cells& operator=(hashed_cells&&) = default;

    void clear() {
        map_.clear();
        block_cells_.clear();
        bounds_ = empty_box();
    }
    std::int64_t clamp_lo(std::size_t) const { return -limit; }
    std::int64_t clamp_hi(std::size_t) const { return limit; }
    // An object beyond +-2^50 cells is listed in the cells at the clamp: on that side those
    // cells reach to infinity, and no distance bound may use their outer face.
    static constexpr bool clamp_cells_hold_beyond = true;
    // Box of every cell that was non-empty since the last clear (grow-only: conservative).
    cell_box<D> bounds() const { return bounds_; }
    const slot_list* find(const key& k) const {
        const auto it = map_.find(k);
        return it == map_.end() ? nullptr : &it->second;
    }
    // Every allocation comes before the first change: the block's record, the cell, room in
    // the block's list of cells, then the slot. If one fails, the cell may be listed empty and
    // is not in its block's list (remove() and grid_core's undo expect exactly that).
    void add(const key& k, slot_index s) {
        std::vector<const cell_node*>& block = block_cells_[block_of(k)];
        cell_node& node = *map_.try_emplace(k).first;
        slot_list& list = node.second;
        if (list.empty()) reserve_for_push(block, 1);
        list.push_back(s);
        if (list.size() == 1) block.push_back(&node);
        grow_bounds(k);
    }
    // Sorted by (the low 32 bits of) the cell's hash, so the entries of one cell are adjacent
    // (a run of equal hashes with different cells, a collision, is sorted by cell); then one
    // map lookup and one reservation per cell. If an insertion fails, the cells before it
    // list their entries (and the failing one may be listed empty: grid_core's undo removes
    // the batch and with it every cell it left empty).
    //
    // The lookups are made in groups (group prefetching, Chen, Ailamaki, Gibbons & Mowry 2004,
    // "Improving hash join performance through prefetching"): for a group of cells, first
    // each cell's bucket and its first node are touched (independent loads the processor
    // overlaps), then the group's lookups and insertions run on cached memory, where a loop
    // of insertions waits for each lookup's misses in turn.
    void add_batch(std::vector<cell_entry<D>>& entries) {
        const teschner_hash<D> hash;
        for (auto& e : entries) e.order = static_cast<std::uint32_t>(hash(e.cell));
        radix_sort_by_order(entries, 32);
        std::vector<std::pair<std::size_t, std::size_t>> cells;  // [first, last) of each cell's entries
        for_each_run(entries, [&](std::size_t a, std::size_t b) {
            bool one_cell = true;
            for (std::size_t i = a + 1; i < b && one_cell; ++i) one_cell = entries[i].cell == entries[a].cell;
            if (!one_cell)
                std::sort(entries.begin() + static_cast<std::ptrdiff_t>(a), entries.begin() + static_cast<std::ptrdiff_t>(b),
                          [](const cell_entry<D>& x, const cell_entry<D>& y) { return x.cell < y.cell; });
            for (std::size_t g = a; g < b;) {
                std::size_t h = g + 1;
                while (h < b && entries[h].cell == entries[g].cell) ++h;
                cells.push_back({g, h});
                g = h;
            }
        });
        constexpr std::size_t group = 16;
        for (std::size_t c0 = 0; c0 < cells.size(); c0 += group) {
            const std::size_t c1 = std::min(cells.size(), c0 + group);
            if (map_.bucket_count() > 0)
                for (std::size_t c = c0; c < c1; ++c) {
                    const std::size_t b = map_.bucket(entries[cells[c].first].cell);
                    const auto first = map_.begin(b);
                    if (first != map_.end(b)) touch(&*first);
                }
            for (std::size_t c = c0; c < c1; ++c) {
                const auto [g, h] = cells[c];
                std::vector<const cell_node*>& block = block_cells_[block_of(entries[g].cell)];
                cell_node& node = *map_.try_emplace(entries[g].cell).first;
                slot_list& list = node.second;
                reserve_for_push(list, h - g);
                const bool was_empty = list.empty();
                if (was_empty) reserve_for_push(block, 1);
                for (std::size_t i = g; i < h; ++i) list.push_back(entries[i].slot);
                if (was_empty) block.push_back(&node);
                grow_bounds(entries[g].cell);
            }
        }
    }
    // Does not allocate. A cell left listed empty by a failed insertion had not been counted.
    void remove(const key& k, slot_index s) {
        const auto it = map_.find(k);
        if (it == map_.end()) return;
        const bool was_empty = it->second.empty();
        it->second.remove(s);
        if (!it->second.empty()) return;
        if (!was_empty) {  // out of its block's list (unordered: swap with the last)
            const auto block = block_cells_.find(block_of(k));
            std::vector<const cell_node*>& cells = block->second;
            *std::find(cells.begin(), cells.end(), &*it) = cells.back();
            cells.pop_back();
            if (cells.empty()) block_cells_.erase(block);
        }
        map_.erase(it);  // the map holds only non-empty cells
    }
    // Whether any cell of block b is non-empty.
    bool block_occupied(const key& b) const {
        const auto it = block_cells_.find(b);
        return it != block_cells_.end() && !it->second.empty();
    }
    // f(b) for each block holding a non-empty cell.
    template <class F>
    void for_each_occupied_block(F&& f) const {
        for (const auto& [b, cells] : block_cells_)
            if (!cells.empty()) f(b);
    }
    // f(cell, list) for each non-empty cell of block b: O(its non-empty cells), no probe of
    // the empty ones (a query far from the data met blocks of 512 cells holding a few).
    template <class F>
    void for_each_nonempty_in_block(const key& b, F&& f) const {
        const auto it = block_cells_.find(b);
        if (it == block_cells_.end()) return;
        for (const cell_node* c : it->second) f(c->first, c->second);
    }
    // Blocks with a count (each holds or held a non-empty cell since it was counted).
    double occupied_blocks() const { return static_cast<double>(block_cells_.size()); }
    double occupied_cells() const { return static_cast<double>(map_.size()); }
    template <class F>
    void for_each_nonempty(F&& f) const {
        for (const auto& [k, list] : map_) f(k, list);
    }
    void reserve(std::size_t n) { map_.reserve(n); }
    std::size_t memory_bytes() const {
        // Node-based maps: one node (key, value, next pointer, cached hash) per cell or block
        // plus the bucket arrays.
        std::size_t b = map_.bucket_count() * sizeof(void*) +
                        map_.size() * (sizeof(key) + sizeof(slot_list) + 2 * sizeof(void*)) +
                        block_cells_.bucket_count() * sizeof(void*) +
                        block_cells_.size() * (sizeof(key) + sizeof(std::vector<const cell_node*>) + 2 * sizeof(void*));
        for (const auto& [k, list] : map_) b += list.heap_bytes();
        for (const auto& [k, cells] : block_cells_) b += cells.capacity() * sizeof(const cell_node*);
        return b;
    }

private:
    template <class V>
    static void touch(const V* p) {
#if defined(__GNUC__) || defined(__clang__)
        __builtin_prefetch(p);
#else
        (void)p;
#endif
    }
    void grow_bounds(const key& k) {
        if (bounds_.empty()) {
            bounds_.lo = bounds_.hi = k;
        } else {
            for (std::size_t i = 0; i < D; ++i) {
                bounds_.lo[i] = std::min(bounds_.lo[i], k[i]);
                bounds_.hi[i] = std::max(bounds_.hi[i], k[i]);
            }
        }
    }
    using cell_map = std::unordered_map<key, slot_list, teschner_hash<D>>;
    using cell_node = typename cell_map::value_type;
    // After a copy of the map: each non-empty cell into its block's list.
    void link_blocks() {
        for (const cell_node& c : map_)
            if (!c.second.empty()) block_cells_[block_of(c.first)].push_back(&c);
    }
    cell_map map_;
    // Per block: its non-empty cells, as pointers to their nodes in map_ (a node-based map
    // keeps a node in place through rehashing, until the cell is erased).
    std::unordered_map<key, std::vector<const cell_node*>, teschner_hash<D>> block_cells_;
    static cell_box<D> empty_box() {
        cell_box<D> b;
        b.lo.fill(1);
        b.hi.fill(0);
        return b;
    }
    cell_box<D> bounds_ = empty_box();
};

}  // namespace spatial::detail
