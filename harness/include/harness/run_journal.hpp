#pragma once
// harness::run_journal — what a suite run has finished, kept on disk case by case, so that a
// run killed halfway (Ctrl-C, SIGTERM, the OOM killer, a lost node) loses no completed case and
// `spatialbench run ... --resume` finishes only the missing ones.
//
// The table itself is still written once, atomically, when every case has passed
// (finish_suite): a killed run never leaves a partial table, and the previous table stays as it
// was. Next to it, from the first completed case on, <results>/<table>.journal/ holds
//   meta.json            the run id, the commit and every option that decides the case list
//                        and its figures (preset, seed, filters, shard, real data);
//   cases/<position>.csv the rows of each completed case (validated before they were
//                        written), each file written atomically;
//   completed.txt        "<position>\t<case id>" per completed case, appended after its file.
// A case is completed once its line is in completed.txt; a file without its line (killed
// between the two writes) is measured again. The journal is removed after the table is written.
//
// Resuming reuses the interrupted run's id, so the finished table is one run, and refuses a
// journal made by another commit or with other options (naming what differs): its rows would
// not be the figures this run measures. A run without --resume refuses to start over a journal
// (naming it), so an interrupted run's cases are never discarded silently.

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "harness/csv_writer.hpp"
#include "harness/suite_options.hpp"

namespace harness {

class run_journal {
public:
    // Opens the journal of options.results_dir / options.output_name for a run `run_id` whose
    // case list is `case_ids` (every case of the suite, in order: positions are indices here).
    // Installs SIGINT/SIGTERM handlers that say what was finished and where the journal is.
    run_journal(const suite_options& options, const std::string& run_id, const std::vector<std::string>& case_ids);
    ~run_journal();
    run_journal(const run_journal&) = delete;
    run_journal& operator=(const run_journal&) = delete;

    // The run's id: the interrupted run's when resuming, else the one given.
    const std::string& run_id() const { return run_id_; }
    const std::filesystem::path& dir() const { return dir_; }

    bool completed(std::size_t position) const { return done_.count(position) != 0; }
    // The rows a completed case wrote.
    const std::vector<result_row>& rows_of(std::size_t position) const { return done_.at(position); }
    // Records a case's rows (its file, then its line in completed.txt).
    void record(std::size_t position, std::vector<result_row> rows);
    // Removes the journal: called once the table holding every case is written, and when the
    // run met a wrong answer (its figures are not kept: "nothing written").
    void finish();

private:
    void update_interrupt_message() const;

    suite_options options_;
    std::string run_id_;
    std::vector<std::string> case_ids_;
    std::filesystem::path dir_;
    std::map<std::size_t, std::vector<result_row>> done_;
    bool on_disk_ = false;  // the folder exists (from the first completed case on)
};

}  // namespace harness
