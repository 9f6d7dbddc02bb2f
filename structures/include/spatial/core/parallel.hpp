#pragma once
// spatial::seq / spatial::par — execution policies of the structures' multi-threaded
// members (bvh: parallel build, batched ray casts; kd_tree; collision_grid's slabs), and the
// primitives they use: parallel_chunks, parallel_for_then (part 0 on the calling thread,
// which goes on before the other parts end) and parallel_invoke.
//
// The back end is oneTBB (Debian's libtbb-dev) when the build defines SPATIAL_HAVE_TBB (the
// CMake target spatial::structures does when TBB is found; option SPATIAL_WITH_TBB).
// Without it `par` runs sequentially and gives the same answers: every parallel member is
// written so that its result does not depend on the schedule. The number of threads is
// TBB's default (all cores) unless the caller limits it, e.g. with tbb::global_control.

#include <cstddef>
#include <exception>
#include <utility>

#if defined(SPATIAL_HAVE_TBB)
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>
#endif

namespace spatial {

struct sequential_policy {};
struct parallel_policy {};
inline constexpr sequential_policy seq{};
inline constexpr parallel_policy par{};

// Whether `par` really runs on several threads in this build.
inline constexpr bool parallel_backend_available =
#if defined(SPATIAL_HAVE_TBB)
    true;
#else
    false;
#endif

namespace detail {

// The number of threads `par` may use here: the back end's for the current task arena (a
// tbb::global_control or task_arena limit included), 1 without one.
inline std::size_t parallel_threads() {
#if defined(SPATIAL_HAVE_TBB)
    return static_cast<std::size_t>(tbb::this_task_arena::max_concurrency());
#else
    return 1;
#endif
}

// Calls body(begin, end) on disjoint chunks covering [0, n), chunks of at least `grain`
// indices, concurrently when the back end allows.
template <class Body>
void parallel_chunks(std::size_t n, std::size_t grain, Body&& body) {
#if defined(SPATIAL_HAVE_TBB)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain == 0 ? 1 : grain),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
#else
    (void)grain;
    if (n > 0) body(std::size_t{0}, n);
#endif
}

// Runs body(k) for every k in [0, n): body(0) on the calling thread, the others as tasks
// that run concurrently when the back end allows; then(), on the calling thread, once body(0)
// has returned (or at once for n = 0), while the others may still run. Returns once none is
// running; the first exception of any of them is rethrown then (then() does not run when
// body(0) threw, and parts not yet started may never start: TBB cancels a task group on an
// exception). For a caller that must hand part 0's results on from its own thread: it does
// so while the slower parts finish.
template <class Body, class Then>
void parallel_for_then(std::size_t n, Body&& body, Then&& then) {
    std::exception_ptr failed;
    auto attempt = [&](auto&& f) {
        try {
            f();
        } catch (...) {
            if (!failed) failed = std::current_exception();
        }
    };
#if defined(SPATIAL_HAVE_TBB)
    tbb::task_group group;  // waited for below whatever happens, so the tasks' references stay valid
    attempt([&] {
        for (std::size_t k = 1; k < n; ++k) group.run([&body, k] { body(k); });
    });
#endif
    attempt([&] {
        if (n > 0) body(std::size_t{0});
        then();
    });
#if defined(SPATIAL_HAVE_TBB)
    attempt([&] { group.wait(); });
#else
    for (std::size_t k = 1; k < n; ++k) attempt([&] { body(k); });
#endif
    if (failed) std::rethrow_exception(failed);
}

// Runs f() and g(), concurrently when the back end allows.
template <class F, class G>
void parallel_invoke(F&& f, G&& g) {
#if defined(SPATIAL_HAVE_TBB)
    tbb::parallel_invoke(std::forward<F>(f), std::forward<G>(g));
#else
    std::forward<F>(f)();
    std::forward<G>(g)();
#endif
}

}  // namespace detail
}  // namespace spatial
