// The subroutine files a program calls (`o<name> call` -> `name.ngc` on the subroutine path).
#pragma once

#include "interp/line_source.hpp"
#include "interp/oword_flow.hpp"
#include "interp/subroutine_path.hpp"

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace gm {

/// The subroutine files a program has called (`o<name> call` -> `name.ngc` on the path), each
/// read like the program: streamed, seeking for loops and returns. At most kMaxOpen are open at
/// once (each holds a read chunk); a file closed for room is opened again when a jump needs it.
class SubroutineFiles : public SubroutineFinder {
 public:
  static constexpr std::size_t kMaxOpen = 4;

  explicit SubroutineFiles(std::vector<std::string> dirs) : path_(std::move(dirs)) {}

  int find(const std::string& label) override;
  std::string miss(const std::string& label) const override { return path_.describe_miss(label); }
  std::string file_name(int id) const override {
    return id > 0 && static_cast<std::size_t>(id) <= files_.size()
               ? files_[static_cast<std::size_t>(id) - 1].path
               : std::string();
  }

  /// The reader of file `id`, opened if needed; null if it cannot be opened.
  LineParser* parser(int id);
  /// Files are read as Fanuc Macro B (--dialect fanuc).
  void set_macro_b(bool on) { macro_b_ = on; }

 private:
  struct File {
    std::string path;
    std::unique_ptr<std::ifstream> in;
    std::unique_ptr<LineParser> parser;
    std::uint64_t used;  ///< clock_ at the last use
  };
  SubroutinePath path_;
  std::vector<File> files_;
  std::uint64_t clock_ = 0;
  bool macro_b_ = false;
};

}  // namespace gm
