// spatial_soak: the operations fuzz target's interpreter (fuzz/operations/) run on seeded
// pseudo-random sequences instead of a fuzzer's inputs, for hours if need be (issue 19, part 5;
// docs/fuzzing.md, "Soak"). Each sequence is up to soak_limits.max_steps operations on a
// structure and brute_force. One step in --validate-every (default 64; 1: every step) is
// validated: its answer compared, the invariants checked after its mutation, and the full
// contents every 16 such intervals and at the end of each sequence (sequence_limits.hpp); the
// oracle applies every mutation, so each validated step compares against the true contents.
// A finding does not stop the run: it is
// counted as a mismatch, its sequence written to a file the fuzz target replays, and the next
// sequence starts; the exit status is 1 if there was any.
//
//   spatial_soak [--structure NAME]... [--operations N] [--seconds T] [--validate-every V] [--seed S] [--first-sequence K] [--findings DIR] [--list]
//   spatial_soak --replay FILE     one written sequence again, every step validated (SPATIAL_FUZZ_TRACE=1: every operation)

#include <algorithm>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

#include "../common/finding.hpp"
#include "../operations/fuzz_input.hpp"
#include "../operations/sequence_limits.hpp"
#include "../operations/soak_file.hpp"
#include "../operations/structure_table.hpp"

namespace {

using spatial_fuzz::named_structure;

// Bytes per sequence: more than soak_limits.max_steps operations read (a step reads a few
// bytes to a few dozen), so a sequence ends at max_steps, not when its bytes run out.
constexpr std::size_t sequence_bytes = 256 * 1024;
// A structure that fails this often is broken: its findings so far are enough to work from.
constexpr std::uint64_t mismatches_before_giving_up = 10;

struct settings {
    std::filesystem::path replay;  // a sequence file to run once instead of soaking
    std::vector<std::string> structures;  // empty: all
    std::uint64_t operations = 10'000'000;
    std::uint64_t seconds = 0;  // per structure; 0: no limit (the operations decide)
    std::uint64_t validate_every = 64;  // sequence_limits::validate_one_in
    std::uint64_t seed = 0;
    // Sequences are numbered per structure and each is a function of (seed, structure,
    // number) alone, so a run that starts at K continues one that ran sequences 0 .. K - 1:
    // a soak longer than one sitting adds up over runs, every sequence a new one.
    std::uint64_t first_sequence = 0;
    std::filesystem::path findings = "soak_findings";
};

[[noreturn]] void usage(const std::string& problem) {
    std::fprintf(stderr,
                 "spatial_soak: %s\n"
                 "usage: spatial_soak [--structure NAME]... [--operations N] [--seconds T] [--validate-every V] [--seed S] [--first-sequence K] [--findings DIR] [--list]\n"
                 "  --structure  a structure of --list (repeatable; default: all)\n"
                 "  --operations operations per structure (default 1e7; 1e7 and 10000000 both read)\n"
                 "  --seconds    also stop a structure after its first sequence that ends past T seconds (default: no limit)\n"
                 "  --validate-every  compare with brute_force at one step in V, full contents every 16 V (default 64; 1: every step)\n"
                 "  --seed       the seed of every sequence (default: random, printed)\n"
                 "  --first-sequence  start at sequence K: continues a run of the same seed that ended after K sequences (default 0)\n"
                 "  --findings   where failing sequences are written (default soak_findings/)\n"
                 "  --replay     run one written sequence, every step validated (SPATIAL_FUZZ_TRACE=1 prints every operation)\n",
                 problem.c_str());
    std::exit(2);
}

std::uint64_t count_argument(const std::string& flag, const std::string& text) {
    std::size_t end = 0;
    double value = 0;
    try {
        value = std::stod(text, &end);
    } catch (const std::exception&) {
        end = 0;
    }
    if (end != text.size() || !(value >= 0) || value > 1.8e19 || value != static_cast<double>(static_cast<std::uint64_t>(value)))
        usage(flag + " '" + text + "' is not a whole number");
    return static_cast<std::uint64_t>(value);
}

settings parse(int argc, char** argv) {
    settings s;
    s.seed = std::random_device{}();
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (flag == "--list") {
            for (const auto& structure : spatial_fuzz::all_structures())
                std::printf("%.*s\n", static_cast<int>(structure.name.size()), structure.name.data());
            std::exit(0);
        }
        if (i + 1 >= argc) usage("missing value after " + flag);
        const std::string value = argv[++i];
        if (flag == "--structure") s.structures.push_back(value);
        else if (flag == "--operations") s.operations = count_argument(flag, value);
        else if (flag == "--seed") s.seed = count_argument(flag, value);
        else if (flag == "--first-sequence") s.first_sequence = count_argument(flag, value);
        else if (flag == "--seconds") s.seconds = count_argument(flag, value);
        else if (flag == "--validate-every") {
            s.validate_every = count_argument(flag, value);
            if (s.validate_every == 0) usage("--validate-every must be at least 1");
        }
        else if (flag == "--findings") s.findings = value;
        else if (flag == "--replay") s.replay = value;
        else usage("unknown option " + flag);
    }
    return s;
}

std::vector<const named_structure*> selected(const settings& s) {
    std::vector<const named_structure*> out;
    for (const auto& structure : spatial_fuzz::all_structures())
        if (s.structures.empty() || std::find(s.structures.begin(), s.structures.end(), structure.name) != s.structures.end())
            out.push_back(&structure);
    for (const auto& name : s.structures)
        if (std::none_of(out.begin(), out.end(), [&](const named_structure* n) { return n->name == name; }))
            usage("no structure '" + name + "' (--list names them)");
    return out;
}

// splitmix64: the seed of one sequence from the run's seed, the structure and the sequence
// number, so that every sequence can be regenerated on its own.
std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

void fill(std::vector<std::uint8_t>& bytes, std::uint64_t seed) {
    std::mt19937_64 random(seed);
    for (std::size_t i = 0; i < bytes.size(); i += 8) {
        const std::uint64_t word = random();
        for (std::size_t k = 0; k < 8 && i + k < bytes.size(); ++k) bytes[i + k] = static_cast<std::uint8_t>(word >> (8 * k));
    }
}

// A file name from a structure name: letters and digits kept, the rest '_'.
std::string file_name_part(std::string_view name) {
    std::string out;
    for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return out;
}

// The sequence running now, for the crash handler: a sanitizer-free build dies on a segfault
// or an abort without a word, and this is what reproduces it.
struct current_sequence {
    std::string header;
    const std::vector<std::uint8_t>* bytes = nullptr;
    std::string crash_file;  // where the handler writes it
};
current_sequence running;

extern "C" void write_sequence_and_die(int signal) {
    // Only async-signal-safe calls: open, write, close, then the default action.
    const int fd = ::open(running.crash_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0 && running.bytes != nullptr) {
        (void)!::write(fd, running.header.data(), static_cast<unsigned>(running.header.size()));
        (void)!::write(fd, running.bytes->data(), static_cast<unsigned>(running.bytes->size()));
        ::close(fd);
        static constexpr char note[] = "\nspatial_soak: crashed; the sequence is written next to the findings (crash-*)\n";
        (void)!::write(2, note, sizeof note - 1);
    }
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

std::filesystem::path write_finding(const settings& s, std::string_view structure, std::uint64_t sequence,
                                    const std::vector<std::uint8_t>& bytes) {
    std::filesystem::create_directories(s.findings);
    const auto file = s.findings / ("soak-" + file_name_part(structure) + "-seed" + std::to_string(s.seed) + "-sequence" +
                                    std::to_string(sequence));
    std::ofstream out(file, std::ios::binary);
    const std::string header = spatial_fuzz::soak_file_header(structure);
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    return file;
}

// The soak's sequence limits with the run's validation interval.
spatial_fuzz::sequence_limits limits_of(const settings& s) {
    spatial_fuzz::sequence_limits limits = spatial_fuzz::soak_limits;
    limits.validate_one_in = static_cast<std::size_t>(s.validate_every);
    return limits;
}

struct structure_result {
    std::uint64_t operations = 0, sequences = 0, mismatches = 0;
    std::size_t largest = 0;           // the most objects a container held
    double mean_largest = 0;           // the per-sequence largest, averaged
    double seconds = 0;
};

structure_result soak(const settings& s, const named_structure& structure, std::size_t structure_index) {
    using clock = std::chrono::steady_clock;
    structure_result r;
    std::vector<std::uint8_t> bytes(sequence_bytes);
    running = {spatial_fuzz::soak_file_header(structure.name), &bytes,
               (s.findings / ("crash-" + file_name_part(structure.name) + "-seed" + std::to_string(s.seed))).string()};
    std::filesystem::create_directories(s.findings);
    const auto start = clock::now();
    auto last_report = start;
    double sum_largest = 0;
    const auto out_of_time = [&] { return s.seconds > 0 && clock::now() - start > std::chrono::seconds(s.seconds); };
    while (r.operations < s.operations && r.mismatches < mismatches_before_giving_up && !out_of_time()) {
        const std::uint64_t sequence = s.first_sequence + r.sequences++;
        fill(bytes, mix(s.seed ^ mix(structure_index ^ mix(sequence))));
        spatial_fuzz::fuzz_input in(bytes.data(), bytes.size());
        std::string problem;
        try {
            const auto done = structure.run(in, structure.name, limits_of(s));
            r.operations += done.operations;
            r.largest = std::max(r.largest, done.largest);
            sum_largest += static_cast<double>(done.largest);
            if (done.operations == 0) throw std::logic_error("a sequence applied no operation");
        } catch (const spatial_fuzz::finding_report& f) {
            problem = f.what;
        } catch (const std::exception& e) {  // the fuzz target's "any other exception"
            problem = std::string("exception escaped: ") + e.what();
        }
        if (!problem.empty()) {
            ++r.mismatches;  // the operations of a failing sequence are not counted
            const auto file = write_finding(s, structure.name, sequence, bytes);
            std::fprintf(stderr, "spatial_soak: MISMATCH in %.*s, sequence %llu: %s\n  replay: fuzz_operations %s\n",
                         static_cast<int>(structure.name.size()), structure.name.data(),
                         static_cast<unsigned long long>(sequence), problem.c_str(), file.c_str());
        }
        if (clock::now() - last_report > std::chrono::seconds(60)) {
            last_report = clock::now();
            std::fprintf(stderr,
                         "spatial_soak:   %.*s: %llu operations, %llu sequences, %llu mismatches so far (to continue: "
                         "--first-sequence %llu)\n",
                         static_cast<int>(structure.name.size()), structure.name.data(),
                         static_cast<unsigned long long>(r.operations), static_cast<unsigned long long>(r.sequences),
                         static_cast<unsigned long long>(r.mismatches),
                         static_cast<unsigned long long>(s.first_sequence + r.sequences));
        }
    }
    r.seconds = std::chrono::duration<double>(clock::now() - start).count();
    if (r.sequences > r.mismatches) r.mean_largest = sum_largest / static_cast<double>(r.sequences - r.mismatches);
    running.bytes = nullptr;
    return r;
}

// Runs a file written by write_finding; 0 if its sequence passes now, 1 if not.
int replay(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<std::uint8_t> content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto sequence = spatial_fuzz::read_soak_file(content.data(), content.size());
    if (!sequence) usage(file.string() + " is not a sequence written by spatial_soak");
    for (const auto& structure : spatial_fuzz::all_structures())
        if (structure.name == sequence->structure) {
            spatial_fuzz::fuzz_input bytes(sequence->data, sequence->size);
            spatial_fuzz::findings_throw() = false;  // a finding aborts, as in the fuzz target
            const auto done = structure.run(bytes, structure.name, spatial_fuzz::soak_limits);
            std::printf("spatial_soak: %s: %zu operations, no mismatch\n", file.c_str(), done.operations);
            return 0;
        }
    usage("no structure '" + std::string(sequence->structure) + "' (--list names them)");
}

}  // namespace

int main(int argc, char** argv) {
    const settings s = parse(argc, argv);
    if (!s.replay.empty()) return replay(s.replay);
    const auto structures = selected(s);
    spatial_fuzz::findings_throw() = true;
    for (int signal : {SIGSEGV, SIGABRT, SIGFPE, SIGILL, SIGBUS}) std::signal(signal, write_sequence_and_die);

    const auto limits = limits_of(s);
    std::printf("spatial_soak: seed %llu, sequences from %llu, %llu operations per structure (or %llu s; 0: no limit), %zu structures, limits: "
                "%zu steps per sequence, %zu objects per container, clear and range erase 1 in %zu; "
                "validated: 1 step in %zu, full contents every %zu steps and at each sequence's end\n",
                static_cast<unsigned long long>(s.seed), static_cast<unsigned long long>(s.first_sequence),
                static_cast<unsigned long long>(s.operations), static_cast<unsigned long long>(s.seconds), structures.size(), limits.max_steps, limits.max_size,
                limits.wholesale_removal_one_in, limits.validate_one_in, 16 * limits.validate_one_in);
    std::printf("%-36s %12s %10s %10s %8s %8s %9s\n", "structure", "operations", "sequences", "mismatches", "largest",
                "mean", "seconds");
    std::fflush(stdout);
    std::uint64_t total_operations = 0, total_mismatches = 0;
    for (const named_structure* structure : structures) {
        const std::size_t index = static_cast<std::size_t>(structure - spatial_fuzz::all_structures().data());
        const structure_result r = soak(s, *structure, index);
        std::printf("%-36.*s %12llu %10llu %10llu %8zu %8.0f %9.1f\n", static_cast<int>(structure->name.size()),
                    structure->name.data(), static_cast<unsigned long long>(r.operations),
                    static_cast<unsigned long long>(r.sequences), static_cast<unsigned long long>(r.mismatches), r.largest,
                    r.mean_largest, r.seconds);
        std::fflush(stdout);
        total_operations += r.operations;
        total_mismatches += r.mismatches;
    }
    std::printf("spatial_soak: seed %llu: %llu operations, %llu mismatches\n", static_cast<unsigned long long>(s.seed),
                static_cast<unsigned long long>(total_operations), static_cast<unsigned long long>(total_mismatches));
    return total_mismatches == 0 ? 0 : 1;
}
