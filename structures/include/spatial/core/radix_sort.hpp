#pragma once
// spatial::detail::radix_sort_by / radix_sort_by_order — least-significant-digit radix sort of
// records by an unsigned key (by their 32-bit `order` member) (Knuth, TAOCP vol. 3, §5.2.5;
// each pass a stable counting sort on at most 11 bits by default), for the bulk operations
// that group a batch by cell or by node and for pair sets (collide/pair_sort.hpp): O(passes (m +
// 2^11)) with passes = ceil(bits / 11), where a comparison sort would cost O(m log m).
// Stable, so records with equal keys keep their input order. Uses one scratch buffer of the
// same size (allocated before `v` changes: if it cannot be allocated, `v` is unchanged).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace spatial::detail {

// Sorts v by key(r), an unsigned integer of which only the low `bits` bits are looked at (the
// higher ones must be 0), in ceil(bits / max_digit) passes of equal digits. `scratch` is
// resized to v's size before v changes (a caller that sorts often keeps it between calls).
template <class Record, class Key>
void radix_sort_by(std::vector<Record>& v, std::vector<Record>& scratch, unsigned bits, Key key,
                   unsigned max_digit = 11) {
    if (v.size() < 2 || bits == 0) return;
    scratch.resize(v.size());
    const unsigned passes = (bits + max_digit - 1) / max_digit;
    const unsigned digit = (bits + passes - 1) / passes;
    const std::size_t radix = std::size_t(1) << digit;
    std::vector<std::size_t> count(radix);
    for (unsigned pass = 0, shift = 0; pass < passes; ++pass, shift += digit) {
        std::fill(count.begin(), count.end(), 0);
        for (const Record& r : v) ++count[(key(r) >> shift) & (radix - 1)];
        std::size_t at = 0;
        for (std::size_t& c : count) {
            const std::size_t k = c;
            c = at;
            at += k;
        }
        for (const Record& r : v) scratch[count[(key(r) >> shift) & (radix - 1)]++] = r;
        v.swap(scratch);
    }
}

// Sorts v by r.order, looking only at its low `bits` bits (the higher ones must be 0).
template <class Record>
void radix_sort_by_order(std::vector<Record>& v, unsigned bits) {
    std::vector<Record> scratch;
    radix_sort_by(v, scratch, bits, [](const Record& r) { return r.order; });
}

// The number of bits needed to hold values below `n` (0 for n <= 1).
inline unsigned bits_below(std::uint64_t n) {
    unsigned b = 0;
    while (b < 64 && (std::uint64_t(1) << b) < n) ++b;
    return b;
}

}  // namespace spatial::detail
