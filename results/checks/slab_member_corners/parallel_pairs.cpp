#include <chrono>
#include <cstdio>
#include <random>
#include <algorithm>
#include "spatial/collide/collision_grid.hpp"
#include "spatial/objects/box.hpp"
using namespace spatial;
using B = objects::box<double,3>;
using P = point<double,3>;
static double now(){ return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
int main(int argc, char** argv){
  std::size_t n = argc>1? std::stoul(argv[1]) : 1000000; int reps = argc>2? std::atoi(argv[2]) : 15;
  std::mt19937_64 r(7); std::uniform_real_distribution<double> u(0,1);
  double s = std::cbrt(2.0/double(n))/2;
  std::vector<B> v; v.reserve(n);
  for(std::size_t i=0;i<n;++i){ P lo{{u(r)*(1-s),u(r)*(1-s),u(r)*(1-s)}}; P hi{{lo[0]+s,lo[1]+s,lo[2]+s}}; v.emplace_back(lo,hi);}
  const collision_grid<B> g(v.begin(), v.end());
  std::size_t threads = detail::parallel_threads();
  std::vector<std::pair<std::uint32_t,std::uint32_t>> found; found.reserve(3*n);
  // One list per part on its own cache lines (session 51): adjacent vectors shared the line
  // of their end pointers, which both threads wrote at every pair.
  struct alignas(64) part { std::vector<std::pair<std::uint32_t,std::uint32_t>> v; void clear(){v.clear();} std::size_t size() const {return v.size();} void emplace_back(std::uint32_t a, std::uint32_t b){v.emplace_back(a,b);} };
  std::vector<part> parts(threads);
  std::vector<double> t1, t2; std::uint64_t c1=0,c2=0;
  for(int rep=0; rep<reps; ++rep){
    double a=now(); found.clear(); g.for_each_self_pair(pair_filter::exact,[&](auto x, auto y){found.emplace_back(x.slot(),y.slot());}); c1=found.size(); t1.push_back(now()-a);
    a=now(); for(auto& p:parts) p.clear(); g.for_each_self_pair_concurrently(par, pair_filter::exact,[&](std::size_t k, auto x, auto y){parts[k].emplace_back(x.slot(),y.slot());}); c2=0; for(auto&p:parts) c2+=p.size(); t2.push_back(now()-a);
  }
  std::sort(t1.begin(),t1.end()); std::sort(t2.begin(),t2.end());
  std::printf("n=%zu pairs %zu/%zu  1t %.2f ms  2t %.2f ms  speedup %.3f (min-based %.3f)\n", n, (size_t)c1,(size_t)c2, t1[reps/2]*1e3, t2[reps/2]*1e3, t1[reps/2]/t2[reps/2], t1[0]/t2[0]);
}
