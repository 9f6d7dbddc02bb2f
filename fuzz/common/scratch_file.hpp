#pragma once
// The fuzzer's bytes as a file: the point-set and mesh readers take a path (and choose the
// format by its extension), so each input is written to one scratch file per extension in a
// directory of this process (several libFuzzer jobs may run side by side), overwritten by the
// next input. The directory is removed when the process exits normally; after a crash the
// input is in libFuzzer's crash-<sha1> file anyway.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <system_error>

#include <unistd.h>

namespace spatial_fuzz {

class scratch_directory {
public:
    scratch_directory()
        : path_(std::filesystem::temp_directory_path() / ("spatial_fuzz_" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path_);
    }
    ~scratch_directory() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    scratch_directory(const scratch_directory&) = delete;
    scratch_directory& operator=(const scratch_directory&) = delete;

    // Writes `bytes` to "input<extension>" in the directory and returns its path.
    std::filesystem::path write(std::string_view extension, std::span<const std::uint8_t> bytes) const {
        std::filesystem::path file = path_ / ("input" + std::string(extension));
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
        return file;
    }

private:
    std::filesystem::path path_;
};

// The one scratch directory of the process (created on first use).
inline const scratch_directory& scratch() {
    static const scratch_directory directory;
    return directory;
}

}  // namespace spatial_fuzz
