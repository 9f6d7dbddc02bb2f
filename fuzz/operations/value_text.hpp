#pragma once
// Values as text for the fuzzer's trace and findings: hexadecimal floats (%a), which read back
// exactly (a double literal in C++17), so a finding's values can be pasted into a test.

#include <cstddef>
#include <cstdio>
#include <string>

#include "spatial/core/object_concepts.hpp"
#include "spatial/core/object_geometry.hpp"

namespace spatial_fuzz {

inline std::string number_text(double v) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%a", v);
    return buffer;
}

// A point as "{x, y, z}"; an object as "{lower...} - {upper...}" (its bounds).
template <class V>
std::string value_text(const V& v) {
    const auto coords = [&](auto coordinate) {
        std::string s = "{";
        for (std::size_t i = 0; i < V::dimension; ++i)
            s += (i ? ", " : "") + number_text(static_cast<double>(coordinate(i)));
        return s + "}";
    };
    if constexpr (spatial::point_object<V>) {
        return coords([&](std::size_t i) { return v[i]; });
    } else {
        return coords([&](std::size_t i) { return spatial::object_lower(v, i); }) + " - " +
               coords([&](std::size_t i) { return spatial::object_upper(v, i); });
    }
}

}  // namespace spatial_fuzz
