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

template <class P>
void require_finite(const P& p, const char* where, const char* what) {
    for (std::size_t i = 0; i < P::dimension; ++i) {
        const auto c = p[i];
        if (!std::isfinite(c)) {
            std::ostringstream os;
            os << where << ": " << what << " has a non-finite coordinate " << i << " = " << c
               << " (NaN and infinity are rejected)";
            throw std::invalid_argument(os.str());
        }
    }
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
    if (!any) throw std::invalid_argument(std::string(where) + ": ray direction is the zero vector");
    if (!(dd > 0) || !std::isfinite(dd))
        throw std::invalid_argument(std::string(where) +
                                    ": ray direction's squared length underflows or overflows; rescale it");
}

template <class T>
void require_nonnegative(T v, const char* where, const char* what) {
    if (!(v >= T(0)) || !std::isfinite(v)) {
        std::ostringstream os;
        os << where << ": " << what << " must be finite and >= 0, got " << v;
        throw std::invalid_argument(os.str());
    }
}

}  // namespace spatial::detail
