#pragma once
// spatial::detail::default_init_allocator<T> — std::allocator, except that the elements a
// std::vector creates without a value (resize(n), emplace_back()) are default-initialised
// instead of value-initialised: a trivially default-constructible T is left unwritten rather
// than zeroed. For an array that is written on every core right after it grows (slot_storage's
// append): a value-initialising resize would zero it on one thread first, and the parallel
// copy would then write it a second time. Construction from a value is std::allocator's.

#include <memory>
#include <new>
#include <type_traits>
#include <utility>

namespace spatial::detail {

template <class T>
struct default_init_allocator : std::allocator<T> {
    using value_type = T;
    default_init_allocator() noexcept = default;
    template <class U>
    default_init_allocator(const default_init_allocator<U>&) noexcept {}
    template <class U>
    struct rebind {
        using other = default_init_allocator<U>;
    };
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        std::allocator_traits<std::allocator<T>>::construct(*this, p, std::forward<Args>(args)...);
    }
    template <class U>
    friend bool operator==(const default_init_allocator&, const default_init_allocator<U>&) noexcept {
        return true;
    }
};

}  // namespace spatial::detail
