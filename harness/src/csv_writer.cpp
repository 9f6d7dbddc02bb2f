#include "harness/csv_writer.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace harness {

// RFC 4180 quoting for fields that need it (params may contain ';' only, but be safe; a bare
// carriage return is quoted too, so that a reader may take CRLF line ends from an edited table).
std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string csv_number(double v) {
    std::ostringstream os;
    os.precision(9);
    os << v;
    return os.str();
}

std::string csv_header() {
    return "suite,structure,bv,workload,n,dim,scalar,operation,params,metric,value,unit,validated,run_id,"
           "repetitions,min,max,check";
}

std::string csv_line(const result_row& r) {
    std::ostringstream os;
    os << csv_field(r.suite) << ',' << csv_field(r.structure) << ',' << csv_field(r.bv) << ','
       << csv_field(r.workload) << ',' << r.n << ',' << r.dim << ',' << csv_field(r.scalar) << ','
       << csv_field(r.operation) << ',' << csv_field(r.params) << ',' << csv_field(r.metric) << ','
       << csv_number(r.value) << ',' << csv_field(r.unit) << ',' << (r.validated() ? "true" : "false") << ','
       << csv_field(r.run_id) << ',' << r.repetitions << ',' << csv_number(r.min_value) << ','
       << csv_number(r.max_value) << ',' << csv_field(r.check);
    return os.str();
}

void write_text_atomically(const std::filesystem::path& file, const std::string& text) {
    std::filesystem::create_directories(file.parent_path().empty() ? "." : file.parent_path());
    const auto tmp = file.string() + ".tmp." + std::to_string(::getpid());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw std::runtime_error("cannot write " + tmp);
        out << text;
        out.flush();
        if (!out) throw std::runtime_error("write failed for " + tmp);
    }
    std::filesystem::rename(tmp, file);
}

void write_csv_atomically(const std::filesystem::path& file, const std::vector<result_row>& rows) {
    std::string text = csv_header() + "\n";
    for (const auto& r : rows) text += csv_line(r) + "\n";
    write_text_atomically(file, text);
}

}  // namespace harness
