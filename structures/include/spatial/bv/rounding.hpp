#pragma once
// Directed rounding of a double result to the volume's scalar T: the fits compute in double
// and must store bounds that still enclose every point after the conversion to T (float
// rounds to nearest, which could cut a point off by half an ulp). O(1).

#include <cmath>
#include <limits>

namespace spatial::detail_rounding {

// The neighbours of x in its own type: the next value above, the next below. Bounds computed
// with one rounding step are pushed one ulp outward with these to stay conservative.
template <class T>
T next_up(T x) {
    return std::nextafter(x, std::numeric_limits<T>::infinity());
}
template <class T>
T next_down(T x) {
    return std::nextafter(x, -std::numeric_limits<T>::infinity());
}

// The smallest T >= v (+inf above T's range: converting such a v is undefined behaviour).
template <class T>
T round_up(double v) {
    if (v > static_cast<double>(std::numeric_limits<T>::max())) return std::numeric_limits<T>::infinity();
    if (v < -static_cast<double>(std::numeric_limits<T>::max())) return std::numeric_limits<T>::lowest();
    T t = static_cast<T>(v);
    if (static_cast<double>(t) < v) t = std::nextafter(t, std::numeric_limits<T>::infinity());
    return t;
}
// The largest T <= v (-inf below T's range).
template <class T>
T round_down(double v) {
    if (v < -static_cast<double>(std::numeric_limits<T>::max())) return -std::numeric_limits<T>::infinity();
    if (v > static_cast<double>(std::numeric_limits<T>::max())) return std::numeric_limits<T>::max();
    T t = static_cast<T>(v);
    if (static_cast<double>(t) > v) t = std::nextafter(t, -std::numeric_limits<T>::infinity());
    return t;
}

}  // namespace spatial::detail_rounding
