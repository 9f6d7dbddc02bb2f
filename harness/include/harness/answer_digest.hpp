#pragma once
// harness::answer_digest: a 64-bit digest of a sequence of answers (indices, distances, their
// counts), fed value by value, that compares two runs' answers without keeping them.
//
// Why: the scene runner compares every step's answers of its timed pass with its validated
// pass's, and each structure's pair sets with the first structure's. Kept whole, those logs
// grew with steps x answers (a 1e6-object scene over 100 steps held about 1.6 GB of pair logs
// per pass, beside the 256 bytes per object that the memory check budgets); a digest per step
// and kind of answer is 8 bytes.
//
// The digest is ORDER-DEPENDENT and includes every sequence's length (add_all), so a missing,
// extra, moved or changed value changes it except with probability about 2^-64 per
// comparison: each value goes through the splitmix64 finaliser (Steele, Lea and Flood 2014,
// "Fast splittable pseudorandom number generators"), an invertible mix in which every input
// bit reaches every output bit, before it is folded into the running state by a multiply-add
// that is itself invertible. Not a cryptographic hash: the answers are not adversarial, only
// possibly wrong. Floating-point values are digested by their bit patterns (the passes must
// agree bit for bit).
#include <bit>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace harness {

class answer_digest {
public:
    void add(std::uint64_t x) { state_ = (state_ ^ mixed(x)) * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull; }
    void add(double x) { add(std::bit_cast<std::uint64_t>(x)); }
    void add(float x) { add(static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(x))); }
    void add(std::uint32_t x) { add(static_cast<std::uint64_t>(x)); }
    template <class A, class B>
    void add(const std::pair<A, B>& p) {
        add(p.first);
        add(p.second);
    }
    // An empty optional and a present one differ whatever the value.
    template <class T>
    void add(const std::optional<T>& x) {
        add(std::uint64_t{x.has_value()});
        if (x) add(*x);
    }
    // The length first, then the elements in order (nested sequences recursively).
    template <class T>
    void add_all(const std::vector<T>& xs) {
        add(static_cast<std::uint64_t>(xs.size()));
        for (const T& x : xs) {
            if constexpr (requires { x.size(); x.begin(); }) add_all(x);
            else add(x);
        }
    }
    std::uint64_t value() const { return mixed(state_); }

private:
    static std::uint64_t mixed(std::uint64_t z) {
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    std::uint64_t state_ = 0x243F6A8885A308D3ull;
};

// The digest of one sequence of answers.
template <class T>
std::uint64_t digest_of(const std::vector<T>& xs) {
    answer_digest d;
    d.add_all(xs);
    return d.value();
}

}  // namespace harness
