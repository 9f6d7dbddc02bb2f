// Uses the installed headers: a kd-tree and a bvh answer one query each; exit status 0 only
// when both answers are right.
#include <cstdio>
#include <vector>

#include "spatial/bvh/bvh.hpp"
#include "spatial/kdtree/kd_tree.hpp"
#include "spatial/objects/box.hpp"

int main() {
    using P = spatial::point<double, 3>;
    const std::vector<P> pts = {P{{0, 0, 0}}, P{{1, 0, 0}}, P{{0, 2, 0}}, P{{0, 0, 3}}};
    const spatial::kd_tree<P> tree(pts.begin(), pts.end());
    const auto nearest = tree.find_nearest(P{{0.9, 0.1, 0}}, 1);
    const bool knn_ok = nearest.size() == 1 && *nearest.front() == pts[1];

    using B = spatial::objects::box<double, 3>;
    const std::vector<B> boxes = {B(P{{0, 0, 0}}, P{{1, 1, 1}}), B(P{{0.5, 0.5, 0.5}}, P{{2, 2, 2}}),
                                  B(P{{5, 5, 5}}, P{{6, 6, 6}})};
    const spatial::bvh<B> hierarchy(boxes.begin(), boxes.end());
    const bool pairs_ok = hierarchy.self_pairs().size() == 1;

    std::printf("kd_tree nearest %s, bvh pairs %s\n", knn_ok ? "right" : "WRONG", pairs_ok ? "right" : "WRONG");
    return knn_ok && pairs_ok ? 0 : 1;
}
