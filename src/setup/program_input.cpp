// A program opened for reading twice: stdin spooled to an unlinked temporary file, one large
// buffer.
#include "setup/program_input.hpp"

#include "common/status.hpp"

#include <fmt/format.h>

#include <unistd.h>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace gm::setup {

ProgramInput::ProgramInput(const std::string& path) : name_(path == "-" ? "<stdin>" : path) {
  std::string open_path = path;
  if (path == "-") {
    // Spooled to a file so control flow can seek in it. Every write is checked: a full disk
    // must not turn into a silently shorter program.
    const char* tmpdir = std::getenv("TMPDIR");
    std::string tmpl = (tmpdir != nullptr && *tmpdir != '\0' ? std::string(tmpdir) : "/tmp") +
                       "/gmotion-stdin-XXXXXX";
    const int fd = mkstemp(tmpl.data());
    if (fd < 0) throw InputError(fmt::format("cannot spool stdin: {}", std::strerror(errno)));
    spool_path_ = tmpl;
    std::FILE* out = fdopen(fd, "wb");
    if (out == nullptr) {
      const int err = errno;
      ::close(fd);
      std::remove(spool_path_.c_str());
      throw InputError(fmt::format("cannot spool stdin: {}", std::strerror(err)));
    }
    char buf[1 << 16];
    std::size_t n;
    int err = 0;  // the first failure's errno
    while (err == 0 && (n = std::fread(buf, 1, sizeof buf, stdin)) > 0)
      if (std::fwrite(buf, 1, n, out) != n) err = errno;
    if (std::fflush(out) != 0 && err == 0) err = errno;
    if (std::fclose(out) != 0 && err == 0) err = errno;
    if (err != 0) {
      std::remove(spool_path_.c_str());  // the destructor does not run for a throwing constructor
      throw InputError(
          fmt::format("cannot spool stdin to {}: {}", spool_path_, std::strerror(err)));
    }
    open_path = spool_path_;
  } else {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
      throw InputError(fmt::format("cannot read program '{}': it is a directory", path));
  }
  // One large buffer: a 27 MB program is read in 27 system calls instead of 3,300, which keeps
  // the slow samples (those that wait for a read) rare.
  buffer_.resize(kBufferBytes);
  file_.rdbuf()->pubsetbuf(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  file_.open(open_path, std::ios::binary);
  if (!file_)
    throw InputError(fmt::format("cannot read program '{}': {}", path, std::strerror(errno)));
  if (!spool_path_.empty()) std::remove(spool_path_.c_str());  // the open stream keeps it alive
}

std::istream& ProgramInput::rewind() {
  file_.clear();
  file_.seekg(0);
  return file_;
}

bool validate_program(ProgramInput& program, const InterpreterOptions& opts) {
  const int errors = count_program_errors(program.rewind(), program.name(), opts, std::cerr);
  if (errors > 0) {
    fmt::print(stderr, "{}: {} error{}\n", program.name(), errors, errors == 1 ? "" : "s");
    return false;
  }
  return true;
}

}  // namespace gm::setup
