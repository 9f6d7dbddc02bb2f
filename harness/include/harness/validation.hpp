#pragma once
// Answer validation. A structure's answers are compared with the oracle's BY DISTANCE
// (ties make identities ambiguous: any set of equidistant points is a right answer), after
// each answer's identities are checked on their own (checked_distances: every reported id
// names a live point, once, at the distance reported for it). Any mismatch throws
// validation_error, which aborts the run before the timing of the wrong answer is recorded.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/point_index.hpp"
#include "spatial/core/distance.hpp"

namespace harness {

struct validation_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Relative tolerance for distances computed by different implementations in scalar T.
template <class T>
constexpr double distance_tolerance() {
    return 64 * static_cast<double>(std::numeric_limits<T>::epsilon());
}

template <class T>
bool same_distance(T a, T b) {
    const double x = a, y = b;
    return std::abs(x - y) <= distance_tolerance<T>() * std::max({1e-300, std::abs(x), std::abs(y)});
}

template <class T>
std::vector<T> sorted_distances(const std::vector<neighbor<T>>& v) {
    std::vector<T> d;
    d.reserve(v.size());
    for (const auto& x : v) d.push_back(x.distance_squared);
    std::sort(d.begin(), d.end());
    return d;
}

// One reported neighbour's identity check: its id names a live point of `s` (point_of) and its
// reported squared distance equals the one recomputed from that point, which is returned.
template <class T, std::size_t D>
T recomputed_distance(point_index<T, D>& s, const spatial::point<T, D>& q, const neighbor<T>& x,
                      const std::string& what) {
    const auto p = s.point_of(x.id);
    if (!p) throw validation_error(what + ": reported id " + std::to_string(x.id) + ", which holds no live point");
    const T recomputed = spatial::squared_distance(*p, q);
    if (!same_distance(recomputed, x.distance_squared)) {
        std::ostringstream os;
        os.precision(17);
        os << what << ": id " << x.id << " reported at squared distance " << x.distance_squared
           << ", but its point lies at " << recomputed;
        throw validation_error(os.str());
    }
    return recomputed;
}

// The identity check of one answer to query q: every reported id names a live point of `s`,
// no id is reported twice, and each reported squared distance equals the one recomputed from
// the point. Returns the recomputed squared distances, sorted: what the answer is then
// compared by. O(k log k) for k reported neighbours.
template <class T, std::size_t D>
std::vector<T> checked_distances(point_index<T, D>& s, const spatial::point<T, D>& q,
                                 const std::vector<neighbor<T>>& answer, const std::string& what) {
    std::vector<T> d;
    std::vector<std::uint32_t> ids;
    d.reserve(answer.size());
    ids.reserve(answer.size());
    for (const auto& x : answer) {
        d.push_back(recomputed_distance(s, q, x, what));
        ids.push_back(x.id);
    }
    std::sort(ids.begin(), ids.end());
    if (const auto twice = std::adjacent_find(ids.begin(), ids.end()); twice != ids.end())
        throw validation_error(what + ": id " + std::to_string(*twice) + " reported twice in one answer");
    std::sort(d.begin(), d.end());
    return d;
}

// The ids one answer has reported so far, as one bit per id: the duplicate check of a radius
// answer in O(k) for k reported points, where sorting the ids (checked_distances) took 61 % of
// a 1e7-point clusters_far run, whose balls reach deep into a dense cluster. Kept between
// answers (forget() clears only the bits an answer set), so a run allocates it once: n / 8 bytes.
class reported_ids {
public:
    // False if `id` was already reported in this answer.
    bool first_report(std::uint32_t id) {
        const std::size_t word = id / 64;
        if (word >= bits_.size()) bits_.resize(word + 1, 0);
        const std::uint64_t bit = std::uint64_t{1} << (id % 64);
        if (bits_[word] & bit) return false;
        bits_[word] |= bit;
        return true;
    }
    template <class T>
    void forget(const std::vector<neighbor<T>>& answer) {
        for (const auto& x : answer)
            if (x.id / 64 < bits_.size()) bits_[x.id / 64] = 0;
    }

private:
    std::vector<std::uint64_t> bits_;
};

// A radius answer's check, compared afterwards by its size alone (require_same_count): every
// reported id names a live point at the distance reported for it (recomputed_distance), none is
// reported twice, and every point lies in the closed ball of squared radius r2. Distinct points
// inside the ball, as many as it holds (`want`: the oracle's or a validated answer's size), are
// exactly the ball's points, so this checks the whole answer keeping one number per query, where
// keeping every distance would not fit (on clusters_far the radius, the median 10th-neighbour
// distance, reaches deep into a dense cluster from the queries near one). Points within
// distance_tolerance of the sphere count as inside: the suites nudge the radius off exact ties.
// O(k) for k reported points; returns k.
template <class T, std::size_t D>
std::size_t checked_ball_answer(point_index<T, D>& s, const spatial::point<T, D>& q,
                                const std::vector<neighbor<T>>& answer, T r2, reported_ids& seen,
                                const std::string& what) {
    struct forget_on_exit {  // leaves `seen` empty for the next answer, also when a check throws
        reported_ids& seen;
        const std::vector<neighbor<T>>& answer;
        ~forget_on_exit() { seen.forget(answer); }
    } forget{seen, answer};
    for (const auto& x : answer) {
        const T d = recomputed_distance(s, q, x, what);
        if (!seen.first_report(x.id))
            throw validation_error(what + ": id " + std::to_string(x.id) + " reported twice in one answer");
        if (d > r2 && !same_distance(d, r2)) {
            std::ostringstream os;
            os.precision(17);
            os << what << ": id " << x.id << " lies at squared distance " << d << ", outside the ball of squared radius "
               << r2;
            throw validation_error(os.str());
        }
    }
    return answer.size();
}

// Exact answers: same count, same sorted squared distances.
template <class T>
void require_same_answer(const std::vector<T>& got, const std::vector<T>& want, const std::string& what) {
    if (got.size() != want.size()) {
        std::ostringstream os;
        os << what << ": " << got.size() << " results, expected " << want.size();
        throw validation_error(os.str());
    }
    for (std::size_t i = 0; i < got.size(); ++i)
        if (!same_distance(got[i], want[i])) {
            std::ostringstream os;
            os.precision(17);
            os << what << ": result " << i << " has squared distance " << got[i] << ", expected " << want[i];
            throw validation_error(os.str());
        }
}

inline void require_same_count(std::size_t got, std::size_t want, const std::string& what) {
    if (got != want) throw validation_error(what + ": " + std::to_string(got) + " results, expected " + std::to_string(want));
}

// (1+eps)-approximate kNN: same count, i-th distance <= (1+eps) * true i-th distance.
template <class T>
void require_approximation(const std::vector<T>& got, const std::vector<T>& exact, double eps,
                           const std::string& what) {
    if (got.size() != exact.size())
        throw validation_error(what + ": wrong number of approximate neighbours");
    const double f = (1 + eps) * (1 + eps) * (1 + distance_tolerance<T>());
    for (std::size_t i = 0; i < got.size(); ++i)
        if (static_cast<double>(got[i]) > f * static_cast<double>(exact[i]) + 1e-300) {
            std::ostringstream os;
            os.precision(17);
            os << what << ": approximate neighbour " << i << " at squared distance " << got[i]
               << " exceeds (1+eps)^2 times the true " << exact[i];
            throw validation_error(os.str());
        }
}

// Recall with ties: the fraction of reported neighbours no farther than the true k-th.
template <class T>
double recall(const std::vector<T>& got, const std::vector<T>& exact) {
    if (exact.empty()) return 1.0;
    const T kth = exact.back();
    std::size_t good = 0;
    for (T d : got) good += d <= kth || same_distance(d, kth);
    return static_cast<double>(good) / static_cast<double>(exact.size());
}

}  // namespace harness
