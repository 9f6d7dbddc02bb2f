// results/checks/ray_hits_and_misses: bvh<triangle<double, 3>> (the default, wide ray layout)
// against Embree (rtcIntersect1, build quality MEDIUM, its default) on the raycast suite's two
// ray sets, built the same way (a 256 x 256 pinhole camera: coherent; 65536 rays from a sphere
// around the mesh towards points in its box: incoherent), each split by whether the ray hits:
// where does the time per ray differ, on rays that reach the mesh or on rays that miss it?
// Also printed: the bvh's own counts per ray (last_query_stats: child boxes entered, triangles
// tested) for the hits and the misses.
// Medians of 9 alternated passes. Each line counts the rays on which the two disagree about
// hitting (float against exact double: grazing rays may); the suite validates the answers.
// Build (one line): g++ -std=c++20 -O3 -DNDEBUG -march=native -ffp-contract=off -Istructures/include
//     -Idatasets/include -isystem /usr/include/eigen3 results/checks/ray_hits_and_misses/ray_hits_and_misses.cpp
//     -o ray_hits_and_misses -lembree3 -ltbb
// Run: ray_hits_and_misses sphere|soup [triangles]
#include <embree3/rtcore.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>
#include "datasets/mesh_generators.hpp"
#include "spatial/bvh/bvh.hpp"
#include "spatial/bvh/bvh_rays.hpp"
using P = spatial::point<double, 3>;
using Tri = spatial::objects::triangle<double, 3>;
struct ray { P o, d; };
static double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
P unit(double x, double y, double z) { double l = std::sqrt(x*x+y*y+z*z); return P{{x/l,y/l,z/l}}; }
int main(int argc, char** argv) {
  std::string name = argc > 1 ? argv[1] : "sphere";
  std::size_t n = argc > 2 ? std::atol(argv[2]) : 1000000;
  auto mesh = datasets::generate_mesh(name, n, 42);
  std::vector<Tri> tris;
  for (auto& t : mesh.triangles) tris.push_back(Tri(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
  P lo = mesh.vertices[0], hi = lo;
  for (auto& v : mesh.vertices) for (int d=0; d<3; ++d) lo[d]=std::min(lo[d],v[d]), hi[d]=std::max(hi[d],v[d]);
  P c; double diag=0; for(int d=0;d<3;++d){c[d]=(lo[d]+hi[d])/2; diag+=(hi[d]-lo[d])*(hi[d]-lo[d]);} diag=std::sqrt(diag);
  // camera rays
  std::vector<ray> coh, inc;
  { double r=diag/2, dist=2.5*r; P back=unit(0.35,0.45,0.82); P eye; for(int d=0;d<3;++d) eye[d]=c[d]+dist*back[d];
    P f{{-back[0],-back[1],-back[2]}}; P right=unit(f[1],-f[0],0); P up{{right[1]*f[2]-right[2]*f[1], right[2]*f[0]-right[0]*f[2], right[0]*f[1]-right[1]*f[0]}};
    double half=r/std::sqrt(dist*dist-r*r); std::size_t side=256;
    for(std::size_t j=0;j<side;++j) for(std::size_t i=0;i<side;++i){ double x=((i+0.5)/side*2-1)*half, y=(1-(j+0.5)/side*2)*half;
      coh.push_back({eye, unit(f[0]+x*right[0]+y*up[0], f[1]+x*right[1]+y*up[1], f[2]+x*right[2]+y*up[2])}); } }
  { std::mt19937_64 rng(5); std::normal_distribution<double> g; std::uniform_real_distribution<double> u; double radius=0.75*diag;
    for(int i=0;i<65536;++i){ P uu=unit(g(rng),g(rng),g(rng)); P o,t; for(int d=0;d<3;++d){o[d]=c[d]+radius*uu[d]; t[d]=lo[d]+(hi[d]-lo[d])*u(rng);} inc.push_back({o,unit(t[0]-o[0],t[1]-o[1],t[2]-o[2])}); } }
  spatial::bvh<Tri> tree(tris.begin(), tris.end());
  tree.prepare_rays();
  RTCDevice dev = rtcNewDevice(nullptr); RTCScene sc = rtcNewScene(dev);
  std::vector<float> vb(3*mesh.vertices.size()+1); for(std::size_t i=0;i<mesh.vertices.size();++i) for(int d=0;d<3;++d) vb[3*i+d]=float(mesh.vertices[i][d]);
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX,0,RTC_FORMAT_FLOAT3,vb.data(),0,12,mesh.vertices.size());
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX,0,RTC_FORMAT_UINT3,mesh.triangles.data(),0,12,mesh.triangles.size());
  rtcCommitGeometry(g); rtcAttachGeometry(sc,g); rtcReleaseGeometry(g); rtcCommitScene(sc);
  auto ours = [&](const std::vector<ray>& rs, std::vector<char>& hit){ double s=0; for(std::size_t i=0;i<rs.size();++i){ spatial::intersect_info<P> info; auto it=tree.intersect_object(rs[i].o, rs[i].d, 0.0, info); hit[i]= it!=tree.end(); if(hit[i]) s+=info.hit_time;} return s; };
  auto emb = [&](const std::vector<ray>& rs, std::vector<char>& hit){ double s=0; for(std::size_t i=0;i<rs.size();++i){ RTCIntersectContext cx; rtcInitIntersectContext(&cx); RTCRayHit rh; rh.ray.org_x=rs[i].o[0]; rh.ray.org_y=rs[i].o[1]; rh.ray.org_z=rs[i].o[2]; rh.ray.dir_x=rs[i].d[0]; rh.ray.dir_y=rs[i].d[1]; rh.ray.dir_z=rs[i].d[2]; rh.ray.tnear=0; rh.ray.tfar=INFINITY; rh.ray.mask=-1; rh.ray.flags=0; rh.ray.time=0; rh.hit.geomID=RTC_INVALID_GEOMETRY_ID; rtcIntersect1(sc,&cx,&rh); hit[i]=rh.hit.geomID!=RTC_INVALID_GEOMETRY_ID; if(hit[i]) s+=rh.ray.tfar;} return s; };
  for (auto* rs : {&coh, &inc}) {
    std::vector<char> h1(rs->size()), h2(rs->size());
    // split into hit and miss sets by our answer
    ours(*rs, h1);
    std::vector<ray> hits, misses; for(std::size_t i=0;i<rs->size();++i) (h1[i]?hits:misses).push_back((*rs)[i]);
    for (auto* sub : {&hits, &misses}) { double v=0,t=0; for (auto& r : *sub) { spatial::intersect_info<P> info; tree.intersect_object(r.o, r.d, 0.0, info); auto st=tree.last_query_stats(); v+=st.nodes_visited; t+=st.objects_tested; }
      std::printf("%s %s %-7s: boxes entered %.1f, triangles tested %.1f per ray\n", name.c_str(), rs==&coh?"coherent":"incoherent", sub==&hits?"hits":"misses", v/sub->size(), t/sub->size()); }
    for (auto* sub : {rs, &hits, &misses}) {
      std::vector<char> a(sub->size()), b(sub->size()); std::vector<double> to, te;
      for (int r=0;r<9;++r){ double t=now(); ours(*sub,a); to.push_back(now()-t); t=now(); emb(*sub,b); te.push_back(now()-t); }
      std::sort(to.begin(),to.end()); std::sort(te.begin(),te.end());
      std::size_t disagree = 0; for (std::size_t i = 0; i < a.size(); ++i) disagree += a[i] != b[i];
      std::printf("%s %s %-7s rays %6zu: ours %.1f ns, embree %.1f ns, ratio %.3f, hit or miss differs on %zu\n", name.c_str(), rs==&coh?"coherent":"incoherent", sub==rs?"all":sub==&hits?"hits":"misses", sub->size(), to[4]/sub->size()*1e9, te[4]/sub->size()*1e9, to[4]/te[4], disagree);
    }
  }
}
