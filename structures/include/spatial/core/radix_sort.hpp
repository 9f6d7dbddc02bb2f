#pragma once
// spatial::detail::radix_sort_by_order — least-significant-digit radix sort of records by
// their 32-bit `order` member (Knuth, TAOCP vol. 3, §5.2.5; each pass a stable counting sort
// on 11 bits), for the bulk operations that group a batch by cell or by node: O(passes (m +
// 2^11)) with passes = ceil(bits / 11), where a comparison sort would cost O(m log m).
// Stable, so records with equal keys keep their input order. Uses one scratch buffer of the
// same size (allocated before `v` changes: if it cannot be allocated, `v` is unchanged).

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace spatial::detail {

// Sorts v by r.order, looking only at its low `bits` bits (the higher ones must be 0).
template <class Record>
void radix_sort_by_order(std::vector<Record>& v, unsigned bits) {
    constexpr unsigned digit = 11;
    constexpr std::size_t radix = std::size_t(1) << digit;
    if (v.size() < 2 || bits == 0) return;
    std::vector<Record> other(v.size());
    for (unsigned shift = 0; shift < bits; shift += digit) {
        std::array<std::size_t, radix> count{};
        for (const Record& r : v) ++count[(r.order >> shift) & (radix - 1)];
        std::size_t at = 0;
        for (std::size_t& c : count) {
            const std::size_t k = c;
            c = at;
            at += k;
        }
        for (const Record& r : v) other[count[(r.order >> shift) & (radix - 1)]++] = r;
        v.swap(other);
    }
}

// The number of bits needed to hold values below `n` (0 for n <= 1).
inline unsigned bits_below(std::uint64_t n) {
    unsigned b = 0;
    while (b < 64 && (std::uint64_t(1) << b) < n) ++b;
    return b;
}

}  // namespace spatial::detail
