// The run journal (see run_journal.hpp).

#include "harness/run_journal.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "harness/result_table.hpp"
#include "harness/run_info.hpp"

namespace harness {

namespace {

namespace fs = std::filesystem;

// Every option that decides the case list or its figures: a journal made with other values
// holds rows this run would not measure.
nlohmann::ordered_json options_meta(const suite_options& o) {
    nlohmann::ordered_json j;
    j["commit"] = git_commit();
    j["suite"] = o.suite_name;
    j["preset"] = o.preset;
    j["seed"] = o.seed;
    j["real_data"] = o.real_data_dir.string();
    j["workloads"] = o.workloads;
    j["structures"] = o.structures;
    j["sizes"] = o.sizes;
    j["cases"] = o.cases;
    j["shard"] = std::to_string(o.shard_index) + "/" + std::to_string(o.shard_count);
    j["dynamic"] = o.dynamic;
    j["all_structures"] = o.all_structures;
    return j;
}

// The message the signal handler writes: two buffers, the handler reads the one published
// last, so a signal during an update sees a whole message (write(2) is async-signal-safe,
// formatting is not).
char interrupt_messages[2][1024];
std::atomic<int> interrupt_message_index{-1};

extern "C" void say_interrupted_and_die(int sig) {
    const int i = interrupt_message_index.load();
    if (i >= 0) {
        const char* m = interrupt_messages[i];
        const ssize_t ignored = ::write(STDERR_FILENO, m, std::strlen(m));
        (void)ignored;
    }
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

std::string read_text(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

run_journal::run_journal(const suite_options& options, const std::string& run_id, const std::vector<std::string>& case_ids)
    : options_(options), run_id_(run_id), case_ids_(case_ids),
      dir_(options.results_dir / (options.output_name + ".journal")) {
    const auto meta = options_meta(options);
    const fs::path meta_file = dir_ / "meta.json";
    // A journal that completed nothing (a run stopped by bad input in its first case) holds
    // nothing to lose: start over.
    if (fs::exists(meta_file) && read_text(dir_ / "completed.txt").find('\n') == std::string::npos) fs::remove_all(dir_);
    if (fs::exists(meta_file)) {
        if (!options.resume)
            throw std::runtime_error(dir_.string() + " holds the completed cases of an interrupted run: rerun with --resume to "
                                     "finish it, or remove that folder to start over");
        nlohmann::ordered_json old;
        try {
            old = nlohmann::ordered_json::parse(read_text(meta_file));
        } catch (const nlohmann::json::exception& e) {
            throw std::runtime_error(meta_file.string() + ": not a journal's meta.json (" + e.what() + ")");
        }
        for (const auto& [key, value] : meta.items())
            if (!old.contains(key) || old[key] != value)
                throw std::runtime_error(dir_.string() + ": the interrupted run had " + key + " = " +
                                         (old.contains(key) ? old[key].dump() : "nothing") + ", this run " + value.dump() +
                                         "; resume with the same commit and options, or remove that folder to start over");
        run_id_ = old.value("run_id", run_id);
        const std::string lines = read_text(dir_ / "completed.txt");
        std::size_t start = 0;
        // Only whole lines count: a line cut by the kill leaves its case to be measured again.
        for (std::size_t end; (end = lines.find('\n', start)) != std::string::npos; start = end + 1) {
            const std::string line = lines.substr(start, end - start);
            const auto tab = line.find('\t');
            const std::size_t position = tab == std::string::npos ? case_ids.size() : std::stoul(line.substr(0, tab));
            if (position >= case_ids.size() || line.substr(tab + 1) != case_ids[position])
                throw std::runtime_error(dir_.string() + "/completed.txt: '" + line + "' is not a case of this run");
            done_[position] = read_results_csv(dir_ / "cases" / (std::to_string(position) + ".csv"));
        }
        on_disk_ = true;
    }
    update_interrupt_message();
    std::signal(SIGINT, say_interrupted_and_die);
    std::signal(SIGTERM, say_interrupted_and_die);
}

run_journal::~run_journal() {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    interrupt_message_index.store(-1);
}

void run_journal::record(std::size_t position, std::vector<result_row> rows) {
    // Created with the first completed case: a run that completes none (a wrong answer or bad
    // input in its first case) leaves the results folder exactly as it was.
    if (!on_disk_) {
        fs::create_directories(dir_ / "cases");
        auto meta = options_meta(options_);
        meta["run_id"] = run_id_;
        write_text_atomically(dir_ / "meta.json", meta.dump(2) + "\n");
        write_text_atomically(dir_ / "completed.txt", "");
        on_disk_ = true;
    }
    write_csv_atomically(dir_ / "cases" / (std::to_string(position) + ".csv"), rows);
    {
        std::ofstream out(dir_ / "completed.txt", std::ios::app);
        out << position << '\t' << case_ids_.at(position) << '\n';
        out.flush();
        if (!out) throw std::runtime_error("cannot append to " + (dir_ / "completed.txt").string());
    }
    done_[position] = std::move(rows);
    update_interrupt_message();
}

void run_journal::finish() {
    interrupt_message_index.store(-1);
    if (on_disk_) fs::remove_all(dir_);
    on_disk_ = false;
}

void run_journal::update_interrupt_message() const {
    const int next = interrupt_message_index.load() == 0 ? 1 : 0;
    std::snprintf(interrupt_messages[next], sizeof interrupt_messages[next],
                  "\nspatialbench: interrupted: %zu case(s) of the %s suite are finished and kept in %s; "
                  "rerun the same command with --resume to finish the others\n",
                  done_.size(), options_.suite_name.c_str(), dir_.c_str());
    interrupt_message_index.store(next);
}

}  // namespace harness
