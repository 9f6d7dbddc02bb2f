// Harness building blocks: the validators must reject wrong answers (they are what stands
// between a bug and a published timing), recall must count ties, CSV must be tidy and
// written atomically, and our containers behind point_index must keep ids straight.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "fuzz/command_line/vocabulary.hpp"
#include "harness/check.hpp"
#include "harness/csv_writer.hpp"
#include "harness/our_indexes.hpp"
#include "harness/run_info.hpp"
#include "harness/structure_registry.hpp"
#include "harness/suite_table.hpp"
#include "harness/timing.hpp"
#include "harness/tuning_sweep.hpp"
#include "harness/validation.hpp"

using namespace harness;

TEST(validation, exact_answers_must_match_in_count_and_distance) {
    EXPECT_NO_THROW(require_same_answer<double>({1, 2, 3}, {1, 2, 3}, "ok"));
    EXPECT_THROW(require_same_answer<double>({1, 2}, {1, 2, 3}, "short"), validation_error);
    EXPECT_THROW(require_same_answer<double>({1, 2, 3.001}, {1, 2, 3}, "far"), validation_error);
    try {
        require_same_answer<double>({1, 5}, {1, 4}, "kd_tree knn query 7");
        FAIL();
    } catch (const validation_error& e) {
        EXPECT_NE(std::string(e.what()).find("kd_tree knn query 7"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("result 1"), std::string::npos);
    }
    // Rounding-level differences between implementations are accepted.
    EXPECT_NO_THROW(require_same_answer<float>({1.0f}, {std::nextafter(1.0f, 2.0f)}, "ulp"));
}

TEST(validation, approximate_answers_must_respect_one_plus_eps) {
    // squared distances: exact 1 and 4; with eps = 1 the bound is (1+1)^2 = 4x.
    EXPECT_NO_THROW(require_approximation<double>({3.9, 15.9}, {1, 4}, 1.0, "ok"));
    EXPECT_THROW(require_approximation<double>({4.1, 4}, {1, 4}, 1.0, "too far"), validation_error);
    EXPECT_THROW(require_approximation<double>({1}, {1, 4}, 1.0, "missing"), validation_error);
}

// A radius answer is checked point by point (live id, distance as reported, inside the closed
// ball, no id twice) and then compared by its size alone; the duplicate bitmap is left empty
// after every answer, also after one that failed, so the next answer is judged on its own.
TEST(validation, radius_answers_are_the_ball_points_when_inside_and_as_many) {
    using P = spatial::point<double, 3>;
    const std::vector<P> pts = {P{{0, 0, 0}}, P{{1, 0, 0}}, P{{0, 2, 0}}, P{{0, 0, 3}}};
    brute_force_index<double, 3> s;
    s.build(pts);
    const P q{{0, 0, 0}};
    const double r2 = 4;
    reported_ids seen;
    std::vector<neighbor<double>> ball;
    s.radius(q, 2, ball);
    ASSERT_EQ(ball.size(), 3u);  // the point at distance 2 lies on the sphere: inside
    EXPECT_EQ((checked_ball_answer<double, 3>(s, q, ball, r2, seen, "on the sphere counts as inside")), 3u);
    EXPECT_EQ((checked_ball_answer<double, 3>(s, q, {}, r2, seen, "empty ball")), 0u);
    EXPECT_NO_THROW(require_same_count(3, 3, "as many as the ball holds"));
    EXPECT_THROW(require_same_count(2, 3, "one missing"), validation_error);

    std::vector<neighbor<double>> twice = ball;
    twice[2] = twice[1];  // as many as the ball holds, but one point stands in for another
    EXPECT_THROW((checked_ball_answer<double, 3>(s, q, twice, r2, seen, "twice")), validation_error);
    EXPECT_EQ((checked_ball_answer<double, 3>(s, q, ball, r2, seen, "after a failed answer")), 3u);

    std::vector<neighbor<double>> outside = ball;
    outside[2] = {9, 3};  // swapped for the point at distance 3
    try {
        checked_ball_answer<double, 3>(s, q, outside, r2, seen, "kd_tree radius query 4");
        FAIL() << "expected validation_error";
    } catch (const validation_error& e) {
        EXPECT_NE(std::string(e.what()).find("kd_tree radius query 4: id 3 lies at squared distance 9"), std::string::npos)
            << e.what();
    }
    std::vector<neighbor<double>> unknown = ball;
    unknown[0].id = 17;
    EXPECT_THROW((checked_ball_answer<double, 3>(s, q, unknown, r2, seen, "unknown id")), validation_error);
}

TEST(validation, recall_counts_ties_at_the_kth_distance_as_correct) {
    EXPECT_DOUBLE_EQ(recall<double>({1, 2, 2}, {1, 2, 2}), 1.0);
    EXPECT_DOUBLE_EQ(recall<double>({1, 2, 9}, {1, 2, 2}), 2.0 / 3.0);
    EXPECT_DOUBLE_EQ(recall<double>({2, 2, 2}, {1, 2, 2}), 1.0);  // other points at the k-th distance
}

// Identity: an answer that names a point twice, names no live point, or misreports a distance
// is wrong even when its sorted distances equal the oracle's (a duplicate standing in for an
// equidistant point is the typical case on lattices and duplicated points).
TEST(validation, answers_are_checked_by_identity_before_distance) {
    using P = spatial::point<double, 3>;
    const std::vector<P> pts = {P{{0, 0, 0}}, P{{1, 0, 0}}, P{{0, 1, 0}}, P{{0, 0, 1}}};
    brute_force_index<double, 3> s;
    s.build(pts);
    const P q{{0, 0, 0}};
    std::vector<neighbor<double>> right;
    s.knn(q, 3, 0, right);
    const auto d = checked_distances<double, 3>(s, q, right, "right");
    EXPECT_EQ(d, (std::vector<double>{0, 1, 1}));

    std::vector<neighbor<double>> twice = right;
    twice[2] = twice[1];  // the same point instead of its equidistant neighbour
    EXPECT_THROW((checked_distances<double, 3>(s, q, twice, "twice")), validation_error);
    EXPECT_NO_THROW(require_same_answer(sorted_distances(twice), d, "distances alone cannot tell"));

    std::vector<neighbor<double>> unknown = right;
    unknown[1].id = 1000;
    EXPECT_THROW((checked_distances<double, 3>(s, q, unknown, "unknown id")), validation_error);

    std::vector<neighbor<double>> misreported = right;
    misreported[0].distance_squared = 0.5;
    EXPECT_THROW((checked_distances<double, 3>(s, q, misreported, "misreported distance")), validation_error);

    s.erase(0);  // erased: its id no longer names a live point
    EXPECT_THROW((checked_distances<double, 3>(s, q, right, "erased")), validation_error);
}

TEST(timing, median_of_repetitions_and_checks_run_on_every_repetition) {
    int before = 0, checks = 0;
    const auto t = time_repeated(
        1, 5, [&] { ++before; }, [&] { return 42; },
        [&](int v) {
            EXPECT_EQ(v, 42);
            ++checks;
        });
    EXPECT_EQ(t.repetitions, 5u);
    EXPECT_EQ(before, 6);
    EXPECT_EQ(checks, 6);
    EXPECT_LE(t.min_seconds, t.median_seconds);
    EXPECT_LE(t.median_seconds, t.max_seconds);
    EXPECT_DOUBLE_EQ(summarize({3, 1, 2}).median_seconds, 2);
    EXPECT_DOUBLE_EQ(summarize({4, 1, 2, 3}).median_seconds, 2.5);
}

TEST(timing, a_long_run_is_timed_once_its_warm_up_included_and_the_others_every_round) {
    int quick_runs = 0, long_runs = 0;
    const std::vector<timed_work> work{
        {"quick", [&] { return double(++quick_runs > 0); }, 1},
        {"long",
         [&] {
             ++long_runs;
             std::this_thread::sleep_for(std::chrono::milliseconds(20));
             return 2.0;
         },
         2}};
    // A 20 ms run is "long" against a 10 ms threshold: its warm-up is its one timed run.
    const auto t = time_interleaved(work, 1, 5, 0.01);
    EXPECT_EQ(quick_runs, 6);
    EXPECT_EQ(long_runs, 1);
    EXPECT_EQ(t[0].repetitions, 5u);
    EXPECT_EQ(t[1].repetitions, 1u);
    EXPECT_GE(t[1].median_seconds, 0.02);
    // Without a warm-up, the first (timed) run is its only one.
    long_runs = 0;
    EXPECT_EQ(time_interleaved(work, 0, 3, 0.01)[1].repetitions, 1u);
    EXPECT_EQ(long_runs, 1);
    // At the default threshold nothing here is long: every round runs.
    long_runs = 0;
    EXPECT_EQ(time_interleaved(work, 0, 3)[1].repetitions, 3u);
    EXPECT_EQ(long_runs, 3);
}

// The collide suite's build_and_self_pairs: a build (short, timed every round) and a query
// (long, timed once). At 1e7 boxes CGAL's query took 12-38 s and its build 0.08 s: the sum
// was taken over the build's rounds, reading a query sample that did not exist (its second
// "total" was a build alone, and the median of the two half the real figure).
TEST(timing, summed_rounds_pair_each_round_and_stop_at_the_shorter_work) {
    const timing_result build = summarize({1, 2, 3}), query = summarize({10});
    const timing_result both = summed_rounds(build, query);
    EXPECT_EQ(both.repetitions, 1u);
    EXPECT_DOUBLE_EQ(both.median_seconds, 11);
    EXPECT_EQ(summed_rounds(query, build).repetitions, 1u);
    const timing_result all = summed_rounds(build, summarize({10, 20, 30}));
    EXPECT_EQ(all.repetitions, 3u);
    EXPECT_DOUBLE_EQ(all.median_seconds, 22);  // the rounds in order: 11, 22, 33
    // Through time_interleaved: the long query's only sample is round 0's.
    const std::vector<timed_work> work{{"build", [] { return 0.0; }, 0},
                                       {"query",
                                        [] {
                                            std::this_thread::sleep_for(std::chrono::milliseconds(20));
                                            return 1.0;
                                        },
                                        1}};
    const auto t = time_interleaved(work, 0, 3, 0.01);
    ASSERT_EQ(t[0].repetitions, 3u);
    ASSERT_EQ(t[1].repetitions, 1u);
    const timing_result sum = summed_rounds(t[0], t[1]);
    EXPECT_EQ(sum.repetitions, 1u);
    EXPECT_DOUBLE_EQ(sum.median_seconds, t[0].samples[0] + t[1].samples[0]);
}

TEST(timing, a_long_repeated_run_ends_the_measurement_after_its_check) {
    int runs = 0, checks = 0;
    const auto sleep_on_run = [&](int long_from) {
        return [&runs, long_from] {
            if (++runs >= long_from) std::this_thread::sleep_for(std::chrono::milliseconds(20));
            return 7;
        };
    };
    const auto check = [&](int v) {
        EXPECT_EQ(v, 7);
        ++checks;
    };
    // A long warm-up is the one timed run, and it was checked.
    auto t = time_repeated(1, 5, [] {}, sleep_on_run(1), check, 0.01);
    EXPECT_EQ(runs, 1);
    EXPECT_EQ(checks, 1);
    EXPECT_EQ(t.repetitions, 1u);
    EXPECT_GE(t.median_seconds, 0.02);
    // Quick runs are timed every repetition until one is long; that one is the last.
    runs = checks = 0;
    t = time_repeated(1, 5, [] {}, sleep_on_run(3), check, 0.01);
    EXPECT_EQ(runs, 3);
    EXPECT_EQ(checks, 3);
    EXPECT_EQ(t.repetitions, 2u);  // runs 2 and 3 (run 1 was the warm-up)
    EXPECT_GE(t.max_seconds, 0.02);
    // At the default threshold nothing here is long.
    runs = checks = 0;
    EXPECT_EQ(time_repeated(0, 3, [] {}, sleep_on_run(1), check).repetitions, 3u);
    EXPECT_EQ(checks, 3);
}

TEST(csv, rows_have_the_documented_columns_and_files_are_replaced_atomically) {
    result_row r;
    r.suite = "knn";
    r.structure = "kd_tree";
    r.workload = "real:a,b.xyz";  // a comma must be quoted
    r.n = 1000;
    r.dim = 3;
    r.scalar = "double";
    r.operation = "knn";
    r.params = "k=10;eps=0.5";
    r.metric = "time_per_op";
    r.value = 123.5;
    r.unit = "ns";
    r.check = "oracle:sample=200+cross:all";
    r.run_id = "knn-smoke-x";
    EXPECT_EQ(csv_header().rfind(
                  "suite,structure,bv,workload,n,dim,scalar,operation,params,metric,value,unit,validated,run_id,", 0),
              0u);
    EXPECT_EQ(csv_line(r).rfind(
                  "knn,kd_tree,,\"real:a,b.xyz\",1000,3,double,knn,k=10;eps=0.5,time_per_op,123.5,ns,true,knn-smoke-x,", 0),
              0u)
        << csv_line(r);
    // `validated` is derived from `check`, the last column: "none" (the default) is not validated.
    EXPECT_EQ(csv_line(r).substr(csv_line(r).rfind(',') + 1), "oracle:sample=200+cross:all");
    result_row unchecked = r;
    unchecked.check = "none";
    EXPECT_NE(csv_line(unchecked).find(",ns,false,"), std::string::npos) << csv_line(unchecked);
    EXPECT_FALSE(result_row{}.validated());
    const auto dir = std::filesystem::temp_directory_path() / "spatialbench_csv_test";
    std::filesystem::remove_all(dir);
    write_csv_atomically(dir / "t.csv", {r});
    write_csv_atomically(dir / "t.csv", {r, r});
    std::ifstream in(dir / "t.csv");
    std::string line;
    int lines = 0;
    while (std::getline(in, line)) ++lines;
    EXPECT_EQ(lines, 3);
    std::size_t files = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
    EXPECT_EQ(files, 1u) << "a temporary file was left behind";
}

TEST(our_indexes, dynamic_ids_survive_bulk_build_duplicates_and_reinsertion) {
    using P = spatial::point<double, 3>;
    kd_tree_index<double, 3> idx("kd_tree");
    std::vector<P> pts;
    for (int i = 0; i < 500; ++i) pts.push_back(P{{double(i % 7), double(i % 5), 0.0}});  // many duplicates
    idx.build(pts);
    idx.prepare_dynamic();
    for (std::uint32_t id = 0; id < 500; id += 2) idx.erase(id);
    EXPECT_EQ(idx.size(), 250u);
    idx.insert(1000, P{{9, 9, 9}});
    idx.insert_near(1000, 1001, P{{9, 9, 8}});
    std::vector<P> batch{P{{7, 7, 7}}, P{{7, 7, 7}}};
    idx.insert_bulk(2000, batch);
    idx.erase(2001);
    idx.erase(1000);
    EXPECT_EQ(idx.size(), 252u);  // 500 - 250 erased + 2 inserted + 2 bulk - 2 erased
    std::vector<neighbor<double>> out;
    idx.knn(P{{7, 7, 7}}, 1, 0, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].distance_squared, 0.0);
    EXPECT_THROW(idx.erase(2001), std::logic_error);  // already erased
}

// The check column's words come out in one order, each once, whatever order the code that ran
// the checks joined them in; nothing checked is "none".
TEST(check_column, words_are_joined_in_one_order_each_once) {
    EXPECT_EQ(check::all_of({check::identity_all, check::cross_all, check::oracle_sample(200)}),
              "oracle:sample=200+cross:all+identity:all");
    EXPECT_EQ(check::all_of({"oracle:all+identity:all", check::cross_all, check::size, check::identity_all}),
              "size+oracle:all+cross:all+identity:all");
    EXPECT_EQ(check::all_of({check::none, ""}), check::none);
}

// The command-line fuzz target does not link the suites and copies their names
// (fuzz/command_line/vocabulary.hpp): the copy must name the runnable suites of the suite table,
// in its order, so that `run --suite NAME` of a new suite is fuzzed too.
TEST(command_line_vocabulary, the_fuzz_targets_copy_names_every_runnable_suite) {
    std::vector<std::pair<std::string, std::string>> runnable, copied;
    for (const auto& s : harness::suite_table())
        if (s.run) runnable.emplace_back(s.name, s.description);
    for (const auto& s : spatial_fuzz::command_line_vocabulary().runnable_suites)
        copied.emplace_back(s.name, s.description);
    EXPECT_EQ(copied, runnable);
}

// Every leaf capacity of the kd_tree's tuning sweep answers kNN and radius queries exactly
// like brute force (the sweep times them next to the default: they must be right too).
TEST(tuning_sweep, every_kd_tree_leaf_capacity_answers_like_brute_force) {
    const std::uint64_t seed = 20261126;
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<spatial::point<double, 3>> pts(3000);
    for (auto& p : pts) p = {u(rng), u(rng), std::floor(u(rng) * 8) / 8};  // ties on z planes
    harness::brute_force_index<double, 3> oracle;
    oracle.build(pts);
    const auto* info = harness::find_structure("kd_tree");
    ASSERT_NE(info, nullptr);
    for (const auto& c : harness::configurations("kd_tree", info->settings, true)) {
        SCOPED_TRACE(harness::params_of(c.settings));
        auto tree = harness::make_kd_tree_index_with_leaf_capacity<double, 3>(
            harness::count_setting(c.settings, "leaf_capacity", "kd_tree"));
        tree->build(pts);
        std::vector<harness::neighbor<double>> got, want;
        for (int q = 0; q < 200; ++q) {
            const spatial::point<double, 3> x{u(rng), u(rng), u(rng)};
            for (std::size_t k : {std::size_t{1}, std::size_t{10}, std::size_t{50}}) {
                tree->knn(x, k, 0.0, got);
                oracle.knn(x, k, 0.0, want);
                ASSERT_EQ(got.size(), want.size());
                for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i].distance_squared, want[i].distance_squared);
            }
            tree->radius(x, 0.1, got);
            oracle.radius(x, 0.1, want);
            auto distances = [](const std::vector<harness::neighbor<double>>& v) {
                std::vector<double> d;
                for (const auto& found : v) d.push_back(found.distance_squared);
                std::sort(d.begin(), d.end());
                return d;
            };
            ASSERT_EQ(distances(got), distances(want));
        }
    }
    EXPECT_THROW((harness::make_kd_tree_index_with_leaf_capacity<double, 3>(12)), std::invalid_argument);
}

// The run sidecar records the process's peak resident memory (what a 1e7 run needed of the
// machine), at least what the process has touched.
TEST(run_sidecar, records_the_peak_resident_memory) {
    constexpr std::size_t touched = std::size_t{64} << 20;
    std::vector<unsigned char> block(touched, 1);  // every page written
    ASSERT_EQ(block.back(), 1);
    EXPECT_GE(harness::peak_resident_bytes(), touched);
    const auto dir = std::filesystem::temp_directory_path() / ("run_sidecar_test_" + std::to_string(getpid()));
    harness::write_run_sidecar(dir, harness::run_info{"peak-run", "knn", "smoke", {}, {}, {}}, 1.0);
    std::ifstream in(dir / "runs" / "peak-run.json");
    const auto sidecar = nlohmann::json::parse(in);
    EXPECT_GE(sidecar.at("peak_rss_bytes").get<std::uint64_t>(), touched);
    std::filesystem::remove_all(dir);
}
