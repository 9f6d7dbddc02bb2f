#pragma once
// spatial::detail::reserve_for_push — room for `more` push_backs made ahead of time, so that a
// structure can do its allocations before its first change and then commit without failing
// (the strong guarantee under std::bad_alloc, docs/contract.md "Exception safety"). The capacity
// is the one the push_backs themselves would have reached (each growth doubles, from 1), so
// memory use, and memory_bytes() figures, are the same as without the reservation.

#include <cstddef>
#include <vector>

namespace spatial::detail {

// `List`: a std::vector, or any list with size(), capacity() and reserve(n) (grid/slot_list.hpp).
template <class List>
void reserve_for_push(List& v, std::size_t more) {
    const std::size_t need = v.size() + more;
    if (need <= v.capacity()) return;
    std::size_t c = v.capacity() == 0 ? 1 : v.capacity();
    while (c < need) c *= 2;
    v.reserve(c);
}

}  // namespace spatial::detail
