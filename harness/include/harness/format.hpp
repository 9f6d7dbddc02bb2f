#pragma once
// Small text helpers shared by the suites' progress lines and validation messages.

#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>

namespace harness {

// n as "1e5" when it is a power of ten, else in full ("99224").
inline std::string fmt_n(std::size_t n) {
    std::ostringstream os;
    const double l = std::log10(static_cast<double>(n));
    if (n > 0 && std::abs(l - std::round(l)) < 1e-9) os << "1e" << static_cast<int>(std::round(l));
    else os << n;
    return os.str();
}

}  // namespace harness
