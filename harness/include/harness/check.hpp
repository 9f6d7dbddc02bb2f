#pragma once
// harness::check — the vocabulary of the CSV `check` column: what verified the answers behind a
// row. The code that runs a check builds its string here, so each word has one place and one
// meaning (documented in docs/harness.md, "The check column"). Words join with '+':
//
//   oracle:all          every answer equal to the brute-force oracle's
//   oracle:sample=N     the answers to N queries (rays, pairs) equal to the oracle's
//   cross:all           every answer equal to the validated reference structure's
//   bound:all           every approximate answer within its (1+eps) bound of the exact one
//   identity:all        every reported element exists, is reported once, and lies at the
//                       distance reported for it (recomputed from the element)
//   contents:all        the structure holds exactly the expected elements (as a multiset),
//                       compared in full after every timed repetition
//   containment:all     every fitted volume contains every input point
//   containment:sample=N  ... N input points, a deterministic stride (the hull's O(facets)
//                       test beyond 1e9 point-facet tests)
//   exact:all           every bounding-volume test agrees with the exact test where it must
//                       (no false negatives)
//   contains:all        every line against a volume agrees with the volume's containment
//                       test (a hit's interval has its middle inside; a miss has none of 64
//                       samples along the line inside)
//   superset:all        every exact answer is among the candidates reported (broad phases:
//                       the candidates have no oracle of their own)
//   cgal:sample=N       the answers for N sampled elements equal CGAL's exact predicates'
//                       (an oracle that shares no code with ours)
//   size                the structure holds exactly the elements it was given
//   derived             computed only from rows that carry a check themselves (ratios)
//   none                nothing verified this figure: `validated` is false
//
// Every timed row also had each timed repetition reproduce the validated answers' checksum
// (timing.hpp); that is implied, not written.

#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

namespace harness::check {

inline const std::string none = "none";
inline const std::string oracle_all = "oracle:all";
inline const std::string cross_all = "cross:all";
inline const std::string bound_all = "bound:all";
inline const std::string identity_all = "identity:all";
inline const std::string contents_all = "contents:all";
inline const std::string containment_all = "containment:all";
inline const std::string exact_all = "exact:all";
inline const std::string contains_all = "contains:all";
inline const std::string superset_all = "superset:all";
inline const std::string size = "size";
inline const std::string derived = "derived";

inline std::string oracle_sample(std::size_t n) { return "oracle:sample=" + std::to_string(n); }
inline std::string containment_sample(std::size_t n) { return "containment:sample=" + std::to_string(n); }
inline std::string cgal_sample(std::size_t n) { return "cgal:sample=" + std::to_string(n); }

// The words of `parts` (each a word or words joined by '+') in one canonical order, each once,
// joined by '+'; empty and "none" parts are skipped, and a check made of no checks is none.
inline std::string all_of(std::initializer_list<std::string> parts) {
    static const std::vector<std::string> order = {"size",  "contents", "oracle",      "cgal",     "cross",   "bound",
                                                   "superset", "containment", "contains", "exact", "identity", "derived"};
    auto rank = [&](const std::string& word) {
        const std::string kind = word.substr(0, word.find(':'));
        const auto it = std::find(order.begin(), order.end(), kind);
        return static_cast<std::size_t>(it - order.begin());
    };
    std::vector<std::string> words;
    for (const auto& p : parts)
        for (std::size_t at = 0; at < p.size();) {
            const std::size_t plus = std::min(p.find('+', at), p.size());
            const std::string word = p.substr(at, plus - at);
            if (!word.empty() && word != none && std::find(words.begin(), words.end(), word) == words.end())
                words.push_back(word);
            at = plus + 1;
        }
    std::stable_sort(words.begin(), words.end(), [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
    std::string out;
    for (const auto& w : words) out += (out.empty() ? "" : "+") + w;
    return out.empty() ? none : out;
}

}  // namespace harness::check
