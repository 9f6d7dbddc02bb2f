// The leaf size of bvh_in_place (issue 18: the ray structure's memory per triangle at most
// twice Embree's). Builds the default bvh and the in-place configuration (leaves tested where
// the container stores them, arrays fitted exactly) at leaves of 4, 6 and 8 triangles on one
// generated mesh, prints memory_bytes() per triangle, then casts the same 1e5 incoherent rays
// (origins on a sphere of 0.75 diagonals around the mesh towards points uniform in its box,
// as the raycast suite's) through each in interleaved rounds: the minimum ns per ray of 5
// rounds, and each over the default's. Every round's sum of hit times must be the same for
// all four trees (exact answers), or the program stops.
//
//   g++ -std=c++20 -O3 -DNDEBUG -march=native -Istructures/include -Idatasets/include
//       -isystem /usr/include/eigen3 results/checks/in_place_leaf_size/in_place_leaves.cpp -o in_place_leaves
//   ./in_place_leaves sphere 1000000; ./in_place_leaves soup 1000000
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>
#include <cmath>
#include "datasets/mesh_generators.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/objects/triangle.hpp"
using tri = spatial::objects::triangle<double,3>;
using P = spatial::point<double,3>;
template <std::size_t L> struct ip : spatial::bvh_config<L> {
  static constexpr spatial::bvh_ray_leaves ray_leaves = spatial::bvh_ray_leaves::in_place;
  static constexpr bool build_headroom = false; };
struct R { P o, d; };
template <class Tree> double cast(const Tree& t, const std::vector<R>& rays, double& sum) {
  auto t0 = std::chrono::steady_clock::now(); sum = 0;
  for (const R& r : rays) { typename Tree::info_type info; auto it = t.intersect_object(r.o, r.d, 0.0, info); if (it != t.end()) sum += info.hit_time; }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / rays.size() * 1e9;
}
int main(int argc, char** argv) {
  const char* w = argc > 1 ? argv[1] : "sphere"; std::size_t n = argc > 2 ? std::stoul(argv[2]) : 1000000;
  auto m = datasets::generate_mesh(w, n, 1);
  std::vector<tri> tris; for (auto& t : m.triangles) tris.emplace_back(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
  P lo{1e300,1e300,1e300}, hi{-1e300,-1e300,-1e300};
  for (auto& v : m.vertices) for (int k=0;k<3;++k){lo[k]=std::min(lo[k],v[k]);hi[k]=std::max(hi[k],v[k]);}
  std::mt19937_64 g(7); std::normal_distribution<double> gs; std::uniform_real_distribution<double> u(0,1);
  double diag = std::sqrt((hi[0]-lo[0])*(hi[0]-lo[0])+(hi[1]-lo[1])*(hi[1]-lo[1])+(hi[2]-lo[2])*(hi[2]-lo[2]));
  std::vector<R> rays;
  for (int i=0;i<100000;++i){ P a{gs(g),gs(g),gs(g)}; double l=std::sqrt(a[0]*a[0]+a[1]*a[1]+a[2]*a[2]); P o,tg,d; for(int k=0;k<3;++k){o[k]=(lo[k]+hi[k])/2+0.75*diag*a[k]/l; tg[k]=lo[k]+(hi[k]-lo[k])*u(g); d[k]=tg[k]-o[k];} double dl=std::sqrt(d[0]*d[0]+d[1]*d[1]+d[2]*d[2]); for(int k=0;k<3;++k) d[k]/=dl; rays.push_back({o,d}); }
  spatial::bvh<tri> def(tris.begin(), tris.end()); def.prepare_rays();
  spatial::bvh<tri, spatial::aabb<double,3>, ip<4>> t4(tris.begin(), tris.end()); t4.prepare_rays();
  spatial::bvh<tri, spatial::aabb<double,3>, ip<6>> t6(tris.begin(), tris.end()); t6.prepare_rays();
  spatial::bvh<tri, spatial::aabb<double,3>, ip<8>> t8(tris.begin(), tris.end()); t8.prepare_rays();
  std::printf("%s n=%zu B/tri: default %.1f  ip4 %.1f  ip6 %.1f  ip8 %.1f\n", w, tris.size(), double(def.memory_bytes())/tris.size(), double(t4.memory_bytes())/tris.size(), double(t6.memory_bytes())/tris.size(), double(t8.memory_bytes())/tris.size());
  double best[4] = {1e30,1e30,1e30,1e30}, s[4];
  for (int round=0; round<5; ++round) {
    best[0]=std::min(best[0],cast(def,rays,s[0])); best[1]=std::min(best[1],cast(t4,rays,s[1]));
    best[2]=std::min(best[2],cast(t6,rays,s[2])); best[3]=std::min(best[3],cast(t8,rays,s[3]));
    if (s[0]!=s[1]||s[0]!=s[2]||s[0]!=s[3]) { std::printf("ANSWERS DIFFER %.17g %.17g %.17g %.17g\n",s[0],s[1],s[2],s[3]); return 1; }
  }
  std::printf("ns/ray min of 5: default %.0f  ip4 %.0f (%.2f)  ip6 %.0f (%.2f)  ip8 %.0f (%.2f)\n", best[0], best[1], best[1]/best[0], best[2], best[2]/best[0], best[3], best[3]/best[0]);
}
