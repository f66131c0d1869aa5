// Reading and writing a suite's stored goldens; zstd for the traces, toml++ for the records.
#include "golden/golden_store.hpp"

#include "common/status.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace gm::golden {
namespace {

namespace fs = std::filesystem;

constexpr int kZstdLevel = 9;

// Writes `bytes` to `p` through a temporary file renamed into place.
void write_atomic(const fs::path& p, std::string_view bytes) {
  const fs::path tmp = p.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    f.close();
    if (!f)
      throw InputError(fmt::format("cannot write '{}': {}", tmp.string(), std::strerror(errno)));
  }
  std::error_code ec;
  fs::rename(tmp, p, ec);
  if (ec) throw InputError(fmt::format("cannot rename '{}': {}", tmp.string(), ec.message()));
}

}  // namespace

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  if (!f) throw InputError(fmt::format("cannot read '{}': {}", p.string(), std::strerror(errno)));
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::optional<StoredCase> read_stored(const fs::path& store, const std::string& name) {
  const fs::path rec = store / (name + ".golden.toml");
  std::error_code ec;
  if (!fs::exists(rec, ec)) return std::nullopt;
  toml::table t;
  try {
    t = toml::parse_file(rec.string());
  } catch (const toml::parse_error& e) {
    throw InputError(
        fmt::format("{}:{}: {}", rec.string(), e.source().begin.line, e.description()));
  }
  StoredCase s;
  s.gmotion_version = t["gmotion_version"].value_or(std::string{});
  const std::string hash = t["setup_hash"].value_or(std::string{});
  s.setup = t["setup"].value_or(std::string{});
  s.program = t["program"].value_or(std::string{});
  s.flags = t["flags"].value_or(std::string{});
  try {
    s.setup_hash = std::stoull(hash, nullptr, 16);
  } catch (const std::exception&) {
    throw InputError(fmt::format("{}: setup_hash '{}' is not a hex number", rec.string(), hash));
  }
  s.trace_zst = store / (name + ".trace.zst");
  s.summary_json = read_text(store / (name + ".summary.json"));
  return s;
}

std::uintmax_t write_stored(const fs::path& store, const std::string& name,
                            const std::string& trace_path, const StoredCase& meta) {
  std::error_code ec;
  fs::create_directories(store, ec);
  if (ec) throw InputError(fmt::format("cannot create '{}': {}", store.string(), ec.message()));
  const std::string raw = read_text(trace_path);
  std::string packed(ZSTD_compressBound(raw.size()), '\0');
  const std::size_t n =
      ZSTD_compress(packed.data(), packed.size(), raw.data(), raw.size(), kZstdLevel);
  if (ZSTD_isError(n) != 0)
    throw InputError(
        fmt::format("zstd: cannot compress '{}': {}", trace_path, ZSTD_getErrorName(n)));
  packed.resize(n);
  write_atomic(store / (name + ".trace.zst"), packed);
  write_atomic(store / (name + ".summary.json"), meta.summary_json);
  toml::table t{{"gmotion_version", meta.gmotion_version},
                {"setup_hash", fmt::format("{:016x}", meta.setup_hash)},
                {"program", meta.program},
                {"flags", meta.flags},
                {"setup", meta.setup}};
  std::ostringstream ss;
  ss << "# A golden recorded by `gmotion golden`; re-record with `gmotion golden verify SUITE "
        "--update`.\n"
     << t << "\n";
  write_atomic(store / (name + ".golden.toml"), ss.str());
  return n;
}

void decompress_file(const fs::path& zst, const std::string& out_path) {
  const std::string packed = read_text(zst);
  const unsigned long long size = ZSTD_getFrameContentSize(packed.data(), packed.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size > (1ULL << 34))
    throw InputError(fmt::format("'{}' is not a zstd-compressed golden trace", zst.string()));
  std::string raw(size, '\0');
  const std::size_t n = ZSTD_decompress(raw.data(), raw.size(), packed.data(), packed.size());
  if (ZSTD_isError(n) != 0 || n != size)
    throw InputError(fmt::format("cannot decompress '{}': {}", zst.string(),
                                 ZSTD_isError(n) != 0 ? ZSTD_getErrorName(n) : "short"));
  std::ofstream f(out_path, std::ios::binary | std::ios::trunc);
  f.write(raw.data(), static_cast<std::streamsize>(raw.size()));
  if (!f) throw InputError(fmt::format("cannot write '{}'", out_path));
}

}  // namespace gm::golden
