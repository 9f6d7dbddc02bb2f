// Standalone timing of kd_tree::find_nearest on building.ply (results/checks/knn_leaf_distances).
// Queries as the knn suite draws them for real data: data points, each coordinate jittered by
// up to 0.1 % of the bounding-box diagonal. Prints the best of 7 rounds per query and a
// checksum of the answers (the same checksum means the same answers).
//
//   g++ -std=c++20 -O3 -march=native -ffp-contract=off -DNDEBUG -I<structures/include> \
//       -I/usr/include/eigen3 knn_building.cpp -o knn_building
//   ./knn_building datasets/real/building.ply K
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "spatial/core/point.hpp"
#include "spatial/kdtree/kd_tree.hpp"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: knn_building FILE.ply K\n");
        return 2;
    }
    using P = spatial::point<double, 3>;
    std::vector<P> points;
    std::ifstream in(argv[1]);
    std::string line;
    while (std::getline(in, line) && line != "end_header") {
    }
    while (std::getline(in, line)) {  // ASCII PLY: x y z first on every vertex line
        std::istringstream fields(line);
        float x, y, z;
        if (fields >> x >> y >> z) points.push_back(P{x, y, z});
    }
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (const P& p : points)
        for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
    double diagonal = 0;
    for (int d = 0; d < 3; ++d) diagonal += (hi[d] - lo[d]) * (hi[d] - lo[d]);
    diagonal = std::sqrt(diagonal);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.001 * diagonal, 0.001 * diagonal);
    std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
    std::vector<P> queries;
    for (int i = 0; i < 200000; ++i) {
        const P& p = points[pick(rng)];
        queries.push_back(P{p[0] + jitter(rng), p[1] + jitter(rng), p[2] + jitter(rng)});
    }
    const spatial::kd_tree<P> tree(points.begin(), points.end());
    const std::size_t k = std::strtoul(argv[2], nullptr, 10);
    double best = 1e300;
    std::size_t checksum = 0;
    for (int round = 0; round < 7; ++round) {
        const auto start = std::chrono::steady_clock::now();
        checksum = 0;
        for (const P& q : queries) {
            const auto found = tree.find_nearest(q, k, 0.0);
            checksum += static_cast<std::size_t>(&*found.back() - &*tree.begin());
        }
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::printf("k=%zu %.1f ns/query checksum %zu\n", k, best / queries.size() * 1e9, checksum);
}
