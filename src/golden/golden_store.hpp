// The recorded goldens of a suite: NAME.trace.zst (binary trace, zstd), NAME.summary.json and
// NAME.golden.toml (gmotion version, set-up hash and text), written atomically.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace gm::golden {

struct StoredCase {
  std::string gmotion_version;
  std::uint64_t setup_hash = 0;
  std::string setup;  ///< the text the hash covers (machine and flags), to name what changed
  std::string program;
  std::string flags;
  std::string summary_json;
  std::filesystem::path trace_zst;
};

/// The stored golden of case `name`, or nullopt when it was never recorded (no NAME.golden.toml).
/// Throws gm::InputError on an unreadable or malformed record.
std::optional<StoredCase> read_stored(const std::filesystem::path& store, const std::string& name);

/// Stores a case: compresses the binary trace at `trace_path`, writes the summary, then the
/// record (last, so a half-written golden is never taken for a whole one). Throws gm::InputError.
/// Returns the compressed trace's size in bytes.
std::uintmax_t write_stored(const std::filesystem::path& store, const std::string& name,
                            const std::string& trace_path, const StoredCase& meta);

/// Decompresses `zst` into `out_path`. Throws gm::InputError.
void decompress_file(const std::filesystem::path& zst, const std::string& out_path);

/// The whole of a file as a string. Throws gm::InputError.
std::string read_text(const std::filesystem::path& p);

}  // namespace gm::golden
