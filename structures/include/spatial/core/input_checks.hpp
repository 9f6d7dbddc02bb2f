#pragma once
// Input validation shared by all containers. Every public entry point validates its input
// BEFORE touching the container, so a rejected call leaves the stored contents unchanged
// (strong exception guarantee). Errors are std::invalid_argument naming the call, the
// argument and the bad value.

#include <cmath>
#include <cstddef>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace spatial::detail {

// Where a check runs: the container's one name (container_base) and the operation, printed
// as "kd_tree::find_nearest". Two pointers, so passing it costs what a string literal costs;
// the text is only joined when a check fails.
struct call_site {
    const char* structure;
    const char* operation;
};
inline std::ostream& operator<<(std::ostream& os, call_site s) { return os << s.structure << "::" << s.operation; }
inline std::string site_text(const char* where) { return where; }
inline std::string site_text(call_site where) { return std::string(where.structure) + "::" + where.operation; }

// The throwing halves live out of line and are marked cold: the checks run on every query
// (a ray cast costs ~0.2-1 us), and with the message formatting inline GCC kept the whole
// check as a call (about 3 ns of every ray; docs/experiments/bvh-rays.md, session 10).
// `Where` is a call_site or a plain "name::operation" string (fits and free functions).
template <class Where, class C>
[[noreturn, gnu::cold, gnu::noinline]] void throw_non_finite(Where where, const char* what, std::size_t i, C c) {
    std::ostringstream os;
    os << where << ": " << what << " has a non-finite coordinate " << i << " = " << c
       << " (NaN and infinity are rejected)";
    throw std::invalid_argument(os.str());
}
template <class Where>
[[noreturn, gnu::cold, gnu::noinline]] void throw_bad_direction(Where where, bool zero) {
    std::ostringstream os;
    os << where
       << (zero ? ": ray direction is the zero vector" : ": ray direction's squared length underflows or overflows; rescale it");
    throw std::invalid_argument(os.str());
}
template <class T, class Where>
[[noreturn, gnu::cold, gnu::noinline]] void throw_negative(T v, Where where, const char* what) {
    std::ostringstream os;
    os << where << ": " << what << " must be finite and >= 0, got " << v;
    throw std::invalid_argument(os.str());
}

template <class P, class Where>
void require_finite(const P& p, Where where, const char* what) {
    for (std::size_t i = 0; i < P::dimension; ++i)
        if (!std::isfinite(p[i])) [[unlikely]]
            throw_non_finite(where, what, i, p[i]);
}

// The direction must be usable: its squared length, in the point's scalar type, must be a
// positive finite number (a direction of 1e-30 in float squares to 0 and is rejected too).
template <class P, class Where>
void require_nonzero_direction(const P& d, Where where) {
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

template <class T, class Where>
void require_nonnegative(T v, Where where, const char* what) {
    if (!(v >= T(0)) || !std::isfinite(v)) [[unlikely]]
        throw_negative(v, where, what);
}

}  // namespace spatial::detail
