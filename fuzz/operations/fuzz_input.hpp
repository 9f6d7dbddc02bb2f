#pragma once
// The fuzzer's bytes read as choices: which operation, which table entry, which element. A
// thin layer over LLVM's FuzzedDataProvider (the structure-aware fuzzing of the libFuzzer
// docs, "Split inputs"/"FuzzedDataProvider"): every choice consumes a few bytes, so a
// mutation of one byte changes one decision and the fuzzer can explore operation sequences
// instead of file formats. When the bytes run out, every choice is the first option.

#include <array>
#include <cstddef>
#include <cstdint>

#include <fuzzer/FuzzedDataProvider.h>

namespace spatial_fuzz {

class fuzz_input {
public:
    fuzz_input(const std::uint8_t* data, std::size_t size) : bytes_(data, size) {}

    bool exhausted() { return bytes_.remaining_bytes() == 0; }
    // A number in [0, n) (0 when n <= 1).
    std::size_t below(std::size_t n) {
        return n <= 1 ? 0 : bytes_.ConsumeIntegralInRange<std::size_t>(0, n - 1);
    }
    bool flag() { return bytes_.ConsumeBool(); }
    // One entry of a table.
    template <class T, std::size_t N>
    const T& pick(const std::array<T, N>& table) {
        return table[below(N)];
    }

private:
    FuzzedDataProvider bytes_;
};

}  // namespace spatial_fuzz
