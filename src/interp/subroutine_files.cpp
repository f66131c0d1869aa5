// Finding `name.ngc` on the subroutine path and keeping a few of those files open for reading.
#include "interp/subroutine_files.hpp"

namespace gm {

int SubroutineFiles::find(const std::string& label) {
  if (path_.empty()) return 0;
  const std::string path = path_.find(label);
  if (path.empty()) return 0;
  for (std::size_t i = 0; i < files_.size(); ++i)
    if (files_[i].path == path) return static_cast<int>(i) + 1;
  files_.push_back(File{path, nullptr, nullptr, 0});
  return static_cast<int>(files_.size());
}

LineParser* SubroutineFiles::parser(int id) {
  File& f = files_.at(static_cast<std::size_t>(id) - 1);
  f.used = ++clock_;
  if (f.parser) return f.parser.get();
  std::size_t open = 0;
  File* oldest = nullptr;
  for (File& g : files_)
    if (g.parser) {
      ++open;
      if (oldest == nullptr || g.used < oldest->used) oldest = &g;
    }
  if (open >= kMaxOpen && oldest != nullptr) {
    oldest->parser.reset();
    oldest->in.reset();
  }
  f.in = std::make_unique<std::ifstream>(f.path, std::ios::binary);
  if (!*f.in) {
    f.in.reset();
    return nullptr;
  }
  f.parser = std::make_unique<LineParser>(*f.in, macro_b_);
  return f.parser.get();
}

}  // namespace gm
