#pragma once
// Whether a call is rejected the way the contract says bad input is rejected: by throwing
// std::invalid_argument (docs/contract.md, "Errors"). Any other exception escapes the fuzz
// target and is reported as a crash: the contract names no other type for bad arguments.

#include <stdexcept>

namespace spatial_fuzz {

template <class F>
bool rejects(F&& call) {
    try {
        call();
    } catch (const std::invalid_argument&) {
        return true;
    }
    return false;
}

}  // namespace spatial_fuzz
