#pragma once
// Silences std::cerr and std::cout for a scope. CGAL's readers report every rejected file
// there (verbose mode), which would bury libFuzzer's own output under millions of lines.
// Only the C++ streams are redirected, not file descriptors 1 and 2, so sanitizer reports,
// libFuzzer's status lines and spatial_fuzz::finding still print. (libFuzzer's
// -close_fd_mask=2 would silence those too.)

#include <iostream>
#include <streambuf>

namespace spatial_fuzz {

class quiet_console {
public:
    quiet_console() : old_err_(std::cerr.rdbuf(&sink_)), old_out_(std::cout.rdbuf(&sink_)) {}
    ~quiet_console() {
        std::cerr.rdbuf(old_err_);
        std::cout.rdbuf(old_out_);
    }
    quiet_console(const quiet_console&) = delete;
    quiet_console& operator=(const quiet_console&) = delete;

private:
    // A stream buffer that accepts and drops every character.
    struct null_buffer : std::streambuf {
        int_type overflow(int_type c) override { return traits_type::not_eof(c); }
        std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
    };
    null_buffer sink_;
    std::streambuf* old_err_;
    std::streambuf* old_out_;
};

}  // namespace spatial_fuzz
