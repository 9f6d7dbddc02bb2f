#pragma once
// Input validation shared by all containers. Every public entry point validates its input
// BEFORE touching the container, so a rejected call leaves the stored contents unchanged
// (strong exception guarantee). Errors are std::invalid_argument naming the call, the
// argument and the bad value.

#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>

namespace spatial::detail {

// The throwing halves live out of line and are marked cold: the checks run on every query
// (a ray cast costs ~0.2-1 us), and with the message formatting inline GCC kept the whole
// check as a call (about 3 ns of every ray; docs/design.md §12.6).
template <class C>
[[noreturn, gnu::cold, gnu::noinline]] void throw_non_finite(const char* where, const char* what, std::size_t i, C c) {
    std::ostringstream os;
    os << where << ": " << what << " has a non-finite coordinate " << i << " = " << c
       << " (NaN and infinity are rejected)";
    throw std::invalid_argument(os.str());
}
[[noreturn, gnu::cold, gnu::noinline]] inline void throw_bad_direction(const char* where, bool zero) {
    throw std::invalid_argument(std::string(where) +
                                (zero ? ": ray direction is the zero vector"
                                      : ": ray direction's squared length underflows or overflows; rescale it"));
}
template <class T>
[[noreturn, gnu::cold, gnu::noinline]] void throw_negative(T v, const char* where, const char* what) {
    std::ostringstream os;
    os << where << ": " << what << " must be finite and >= 0, got " << v;
    throw std::invalid_argument(os.str());
}

template <class P>
void require_finite(const P& p, const char* where, const char* what) {
    for (std::size_t i = 0; i < P::dimension; ++i)
        if (!std::isfinite(p[i])) [[unlikely]]
            throw_non_finite(where, what, i, p[i]);
}

// The direction must be usable: its squared length, in the point's scalar type, must be a
// positive finite number (a direction of 1e-30 in float squares to 0 and is rejected too).
template <class P>
void require_nonzero_direction(const P& d, const char* where) {
    require_finite(d, where, "ray direction");
    typename P::scalar_type dd = 0;
    bool any = false;
    for (std::size_t i = 0; i < P::dimension; ++i) {
        dd += d[i] * d[i];
        any |= d[i] != 0;
    }
    if (!any) [[unlikely]]
        throw_bad_direction(where, true);
    if (!(dd > 0) || !std::isfinite(dd)) [[unlikely]]
        throw_bad_direction(where, false);
}

template <class T>
void require_nonnegative(T v, const char* where, const char* what) {
    if (!(v >= T(0)) || !std::isfinite(v)) [[unlikely]]
        throw_negative(v, where, what);
}

}  // namespace spatial::detail
