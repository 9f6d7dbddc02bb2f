#pragma once
// The file the soak tool (fuzz/soak/) writes for a failing sequence, which the operations fuzz
// target replays: a header line naming the structure, then the sequence's bytes. The name,
// not the first byte of a fuzzing input, picks the structure, because the soak always has the
// full matrix and a fuzz build may have the core one (structure_table.hpp); and the header
// tells the target to read the bytes with the soak's limits (sequence_limits.hpp), without
// which the same bytes are another sequence.
//
//   spatial-soak <structure name>\n<bytes>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace spatial_fuzz {

inline constexpr std::string_view soak_file_magic = "spatial-soak ";

inline std::string soak_file_header(std::string_view structure) {
    return std::string(soak_file_magic) + std::string(structure) + "\n";
}

struct soak_sequence {
    std::string_view structure;
    const std::uint8_t* data;
    std::size_t size;
};

// The structure and bytes of a soak file; nothing when the input has no soak header.
inline std::optional<soak_sequence> read_soak_file(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    if (!text.starts_with(soak_file_magic)) return std::nullopt;
    const std::size_t end_of_line = text.find('\n');
    if (end_of_line == std::string_view::npos) return std::nullopt;
    const std::string_view name = text.substr(soak_file_magic.size(), end_of_line - soak_file_magic.size());
    return soak_sequence{name, data + end_of_line + 1, size - end_of_line - 1};
}

}  // namespace spatial_fuzz
