#pragma once
// spatial::container_base<Derived, O> — what every structure of the library shares, written
// once (the CRTP pattern of nanoflann's KDTreeBaseClass): the element store with its stable
// handles, the STL basics, the contract's forwarding overloads, the ray thickness, the
// range-erase rule, and error messages built from the structure's one name.
//
// A structure derives from it and supplies, besides its own queries:
//   static constexpr const char* structure_name = "kd_tree";   // the ONE place of its name
//   iterator intersect_object(origin, direction, thickness, info) const;
//   std::vector<iterator> find_nearest(x, k, eps) const;
//   void erase_slots(std::span<const slot_index>);  // remove these (still stored) slots
//   void rebuild_survivors();  // the slots were released: rebuild the index over the rest
// and brings the base's names into scope next to its own with SPATIAL_CONTAINER_BASE_MEMBERS
// (below), because a member declared in the derived class hides the base's members of that
// name and a dependent base's names are not found otherwise.
//
// Range erase, "a quarter or more means rebuild": erasing m of n elements one by one costs
// m removals with their local repairs, O(m log n) for the trees; releasing the m slots and
// rebuilding the index over the n - m survivors costs O(n log n) once and leaves a balanced,
// tight index. Past m >= n/4 the rebuild is cheaper and better (measured for the kd-tree in
// docs/experiments), so every structure applies the same threshold.
//
// Complexity of what lives here: size/empty/begin/end O(1) (begin skips free slots, O(1)
// amortised over an iteration); range erase O(m) plus the structure's erase_slots or rebuild.

#include <cstddef>
#include <new>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "spatial/core/input_checks.hpp"
#include "spatial/core/intersect_info.hpp"
#include "spatial/core/object_concepts.hpp"
#include "spatial/core/slot_storage.hpp"

namespace spatial {

template <class Derived, stored_object O>
class container_base {
public:
    using value_type = O;
    using point_type = point_type_of<O>;
    using scalar_type = typename O::scalar_type;
    using size_type = std::size_t;
    using iterator = slot_iterator<O>;
    using const_iterator = iterator;
    using info_type = intersect_info<point_type>;
    static constexpr std::size_t dimension = O::dimension;

    // ---- ray cast: the two bool forms of the contract ------------------------------------
    // True iff an object is hit before info.hit_time; `info` then describes the nearest hit.
    // Without a thickness, the container's ray_thickness() is used.
    bool intersect(const point_type& origin, const point_type& direction, info_type& info) const {
        return self().intersect_object(origin, direction, ray_thickness_, info) != self().end();
    }
    bool intersect(const point_type& origin, const point_type& direction, scalar_type thickness,
                   info_type& info) const {
        return self().intersect_object(origin, direction, thickness, info) != self().end();
    }
    scalar_type ray_thickness() const { return ray_thickness_; }
    void set_ray_thickness(scalar_type t) {
        detail::require_nonnegative(t, site("set_ray_thickness"), "thickness");
        ray_thickness_ = t;
    }

    // ---- nearest neighbours: the exact form ------------------------------------------------
    std::vector<iterator> find_nearest(const point_type& x, size_type k) const {
        return self().find_nearest(x, k, scalar_type(0));
    }

    // ---- range erase -------------------------------------------------------------------
    // Erases [first, last). Past a quarter of the container the survivors are rebuilt once
    // (see the header comment); otherwise the structure removes each slot with its repairs.
    // Strong guarantee under allocation failure: what can fail to allocate (the list, the
    // free-list room) comes first; both hooks leave the structure as it was when they throw
    // std::bad_alloc. A rebuild that cannot allocate gives its slots back and the range is
    // removed one by one instead.
    void erase(const_iterator first, const_iterator last) {
        std::vector<slot_index> doomed;
        for (; first != last; ++first) doomed.push_back(first.slot());
        if (doomed.empty()) return;
        slots_.reserve_releases(doomed.size());
        if (doomed.size() * 4 >= slots_.size()) {
            std::vector<typename slot_storage<O>::meta_type> metas;
            metas.reserve(doomed.size());
            for (slot_index s : doomed) metas.push_back(slots_.meta(s));
            for (slot_index s : doomed) slots_.release(s);
            try {
                self().rebuild_survivors();
                return;
            } catch (const std::bad_alloc&) {
                for (std::size_t i = doomed.size(); i-- > 0;) slots_.undo_release(doomed[i], metas[i]);
            }
        }
        self().erase_slots(std::span<const slot_index>(doomed));
    }

    // ---- STL basics --------------------------------------------------------------------
    size_type size() const { return slots_.size(); }
    bool empty() const { return slots_.size() == 0; }
    iterator begin() const { return make(slots_.next_occupied(0)); }
    iterator end() const { return make(static_cast<slot_index>(slots_.capacity())); }

protected:
    container_base() = default;
    // The structure's name and an operation, for error messages ("octree::insert: ...").
    static constexpr detail::call_site site(const char* operation) { return {Derived::structure_name, operation}; }
    iterator make(slot_index s) const { return iterator(&slots_, s); }
    // For the structures' move/swap: the base's state travels with the elements.
    void swap_base(container_base& o) noexcept {
        std::swap(slots_, o.slots_);
        std::swap(ray_thickness_, o.ray_thickness_);
    }
    // A structure's swap_contents in one line: the base's state and the listed members of
    // Derived (pointers to members: &Derived::nodes_, ...) are swapped with o's. Cannot throw
    // when the members' swaps cannot (vectors, scalars), which the structures' noexcept moves
    // rely on.
    template <class... Member>
    void swap_with(Derived& o, Member Derived::*... members) noexcept((std::is_nothrow_swappable_v<Member> && ...)) {
        swap_base(o);
        (std::swap(self().*members, o.*members), ...);
    }
    // A structure's move assignment: *this is cleared, then takes o's contents by
    // Derived::swap_contents, so o is left empty and usable (self-assignment does nothing).
    // Cannot throw when the structure's clear() and swap_contents cannot (none allocates).
    Derived& move_assign_from(Derived& o) {
        if (&self() != &o) {
            self().clear();
            self().swap_contents(o);
        }
        return self();
    }

    slot_storage<O> slots_;
    scalar_type ray_thickness_ = 0;

private:
    const Derived& self() const { return static_cast<const Derived&>(*this); }
    Derived& self() { return static_cast<Derived&>(*this); }
};

}  // namespace spatial

// Brings container_base's member types and public members into a structure's scope: names of
// a dependent base are not found by unqualified lookup, and a structure's own insert/erase/
// find_nearest/intersect would hide the base's overloads of the same name. `Base` is the
// structure's alias of its container_base.
#define SPATIAL_CONTAINER_BASE_MEMBERS(Base) \
    using typename Base::const_iterator;     \
    using typename Base::info_type;          \
    using typename Base::iterator;           \
    using typename Base::point_type;         \
    using typename Base::scalar_type;        \
    using typename Base::size_type;          \
    using Base::begin;                       \
    using Base::dimension;                   \
    using Base::empty;                       \
    using Base::end;                         \
    using Base::erase;                       \
    using Base::find_nearest;                \
    using Base::intersect;                   \
    using Base::size
