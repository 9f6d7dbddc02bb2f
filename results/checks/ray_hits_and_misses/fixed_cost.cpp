// results/checks/ray_hits_and_misses: the fixed cost of a ray. bvh<triangle<double, 3>> on the
// 1e6 sphere, the raycast suite's 256 x 256 camera rays split into those that miss the mesh
// (about 1 child box entered a ray: the setup and the root node are all their cost) and those
// that hit it; medians of 31 passes, the hits' distances summed as a checksum (must not
// change between builds).
// Build (one line): g++ -std=c++20 -O3 -DNDEBUG -march=native -ffp-contract=off -Istructures/include
//     -Idatasets/include -isystem /usr/include/eigen3 results/checks/ray_hits_and_misses/fixed_cost.cpp
//     -o fixed_cost -ltbb
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>
#include "datasets/mesh_generators.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/bvh/bvh_rays.hpp"
using P = spatial::point<double, 3>;
using Tri = spatial::objects::triangle<double, 3>;
struct ray { P o, d; };
static double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
P unit(double x, double y, double z) { double l = std::sqrt(x*x+y*y+z*z); return P{{x/l,y/l,z/l}}; }
int main() {
  auto mesh = datasets::generate_mesh("sphere", 1000000, 42);
  std::vector<Tri> tris;
  for (auto& t : mesh.triangles) tris.push_back(Tri(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
  P lo = mesh.vertices[0], hi = lo;
  for (auto& v : mesh.vertices) for (int d=0; d<3; ++d) lo[d]=std::min(lo[d],v[d]), hi[d]=std::max(hi[d],v[d]);
  P c; double diag=0; for(int d=0;d<3;++d){c[d]=(lo[d]+hi[d])/2; diag+=(hi[d]-lo[d])*(hi[d]-lo[d]);} diag=std::sqrt(diag);
  std::vector<ray> coh;
  { double r=diag/2, dist=2.5*r; P back=unit(0.35,0.45,0.82); P eye; for(int d=0;d<3;++d) eye[d]=c[d]+dist*back[d];
    P f{{-back[0],-back[1],-back[2]}}; P right=unit(f[1],-f[0],0); P up{{right[1]*f[2]-right[2]*f[1], right[2]*f[0]-right[0]*f[2], right[0]*f[1]-right[1]*f[0]}};
    double half=r/std::sqrt(dist*dist-r*r); std::size_t side=256;
    for(std::size_t j=0;j<side;++j) for(std::size_t i=0;i<side;++i){ double x=((i+0.5)/side*2-1)*half, y=(1-(j+0.5)/side*2)*half;
      coh.push_back({eye, unit(f[0]+x*right[0]+y*up[0], f[1]+x*right[1]+y*up[1], f[2]+x*right[2]+y*up[2])}); } }
  spatial::bvh<Tri> tree(tris.begin(), tris.end());
  tree.prepare_rays();
  std::vector<ray> miss, hit;
  for (auto& r : coh) { spatial::intersect_info<P> info; (tree.intersect_object(r.o, r.d, 0.0, info) == tree.end() ? miss : hit).push_back(r); }
  for (auto* set : {&miss, &hit}) {
  std::vector<double> t; double s = 0;
  for (int k = 0; k < 31; ++k) { double a = now(); for (auto& r : *set) { spatial::intersect_info<P> info; if (tree.intersect_object(r.o, r.d, 0.0, info) != tree.end()) s += info.hit_time; } t.push_back(now() - a); }
  std::sort(t.begin(), t.end());
  std::printf("%s %zu: %.2f ns/ray (checksum %.17g)\n", set == &miss ? "misses" : "hits", set->size(), t[15] / set->size() * 1e9, s);
  }
}
