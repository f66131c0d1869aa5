// Where the interpreter's lines come from: reading and parsing (LineParser), the current file
// after jumps (LineSource) and the read-ahead thread (ParallelFront).
#pragma once

#include "common/batch_ring.hpp"
#include "common/diagnostic.hpp"
#include "grammar/parse.hpp"
#include "interp/block_words.hpp"
#include "interp/line_reader.hpp"
#include "interp/move_tally.hpp"
#include "interp/oword_flow.hpp"

#include <array>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace gm {

/// One line as read and parsed: what the front half (reader + grammar) hands to the back half
/// (program rules + interpreter). Reused from line to line.
struct ParsedLine {
  int number = 0;                 ///< 1-based line number
  std::uint64_t offset = 0;       ///< byte offset of the line in the program
  std::uint64_t next_offset = 0;  ///< byte offset of the line after it
  bool truncated = false;         ///< longer than grammar::kMaxLineLength (not parsed)
  int file = 0;                   ///< 0: the program; > 0: a subroutine file
  std::string text;               ///< the line as read (diagnostics echo it)
  grammar::Block block;
  /// The read-ahead thread's import of `block`'s words (importable_ahead lines of the LinuxCNC
  /// dialect), valid when `imported`; the interpreter then skips its own.
  BlockWords words;
  bool imported = false;

  /// Gives back memory a hostile line made this slot grow (kept lines stay small).
  void trim() {
    if (text.capacity() > kKeepBytes) std::string().swap(text);
    if (block.words.capacity() > kKeepWords) std::vector<grammar::Word>().swap(block.words);
  }
  static constexpr std::size_t kKeepBytes = std::size_t{1} << 16;
  static constexpr std::size_t kKeepWords = 1024;
};

/// The front half: reads and parses lines. Holds no interpreter state, so it can run ahead on
/// another thread.
class LineParser {
 public:
  /// `macro_b`: read Fanuc Macro B (--dialect fanuc; grammar::BlockParser::set_macro_b).
  explicit LineParser(std::istream& in, bool macro_b = false)
      : reader_(in, grammar::kMaxLineLength) {
    parser_.set_macro_b(macro_b);
  }
  /// Reads and parses the next line into `p`. False at end of input.
  bool next(ParsedLine& p);
  /// Number of the last line read (0 before the first).
  int last_number() const { return reader_.number(); }
  /// Continues at byte `offset`, the line there being numbered `line`. False if the input
  /// cannot seek. From then on parsed lines are cached.
  bool seek(std::uint64_t offset, int line) {
    if (!looped_) cache_.resize(std::size_t{1} << kCacheBits);
    looped_ = true;
    return reader_.restart(offset, line - 1);
  }

 private:
  /// 256 lines of at most 256 bytes each (LinuxCNC's own limit is 253): loop bodies fit, and a
  /// hostile program cannot make the cache hold more than about 256 × a parsed line.
  static constexpr int kCacheBits = 8;
  static constexpr std::size_t kCacheLineBytes = 256;
  struct Cached {
    std::uint64_t offset = ~std::uint64_t{0};
    int number = 0;
    std::string text;
    grammar::Block block;
  };
  LineReader reader_;
  grammar::BlockParser parser_;
  bool looped_ = false;
  std::vector<Cached> cache_;  ///< direct-mapped by offset; empty until the first seek
};

class ProgramRunner;

/// Where the serial driver reads: the program, or a subroutine file after a call jumped there.
class LineSource {
 public:
  LineSource(LineParser& program, ProgramRunner& back) : program_(program), back_(back) {}
  /// The next line of the current file (tagged with it). False at its end.
  bool next(ParsedLine& p) {
    if (!current().next(p)) return false;
    p.file = file_;
    return true;
  }
  int last_number() { return current().last_number(); }
  int file() const { return file_; }
  /// Continues where `jump` says; false (with the error reported) if that is impossible.
  bool go(const FlowJump& jump, int from_line, std::vector<Diagnostic>& diags);

 private:
  LineParser& current();
  LineParser& program_;
  ProgramRunner& back_;
  int file_ = 0;
};

/// Reading and parsing on a second thread, in batches, ahead of the interpreter on this one.
/// Same diagnostics, in the same order, and the same summary as the serial check: the front
/// half has no state the back half changes. A batch closes at kBatchLines lines or kBatchBytes
/// bytes of text, so at most kBatches batches of bounded size are in memory. The hand-over is
/// the run's own queue type, BatchRing.
///
/// With a MoveTally (check's summary) the work goes the other way too: the interpreter's thread
/// writes each command's TallyEntry into the batch of its line (defer), and this thread adds the
/// entries up when the batch comes back to be refilled, in the order the batches were handed
/// back; what it has not added when it stops is added on the interpreter's thread, so the sums
/// are the serial ones, bit for bit.
class ParallelFront {
 public:
  static constexpr std::size_t kBatches = 3;
  static constexpr std::size_t kBatchLines = 1024;
  static constexpr std::size_t kBatchBytes = std::size_t{1} << 20;
  /// Tally entries a batch holds at most: a block of many moves (a canned cycle's repeats) adds
  /// its entries up on the interpreter's thread beyond this, once the earlier batches are added.
  static constexpr std::size_t kTallyEntries = 4096;

  struct Batch {
    /// Grows as lines are read, to kBatchLines at most: a short program builds only its lines
    /// (3 × 1,024 built up front cost a small program's check more than reading it).
    std::vector<ParsedLine> lines;
    std::size_t count = 0;
    bool eof = false;     ///< the input ends after these lines
    int last_number = 0;  ///< with eof: the last line number read
    /// The summary's entries of these lines' commands, the first tally_count (defer).
    std::vector<TallyEntry> tally;
    std::size_t tally_count = 0;
  };

  /// `import_axes`: the machine's axes when the lines' words are imported here (LinuxCNC's
  /// dialect, whose rules change no word before the interpreter), else null. `tally`: where the
  /// deferred entries are added up (null: none are).
  explicit ParallelFront(std::istream& in, bool macro_b = false,
                         const AxisLayout* import_axes = nullptr, MoveTally* tally = nullptr)
      : front_(in, macro_b),
        import_axes_(import_axes),
        import_axis_bits_(import_axes != nullptr ? program_axis_bits(*import_axes) : 0),
        tally_(tally),
        thread_([this] { produce(); }) {}
  /// Stops the reader; adds up the entries it has not.
  ~ParallelFront();
  ParallelFront(const ParallelFront&) = delete;
  ParallelFront& operator=(const ParallelFront&) = delete;

  /// Waits for the next batch; rethrows what the reader thread threw. The consumer stops
  /// asking after the batch marked eof, so a batch always comes.
  Batch& acquire() {
    taken_ = ring_.begin_take();
    return *taken_;
  }
  /// Hands the batch returned by acquire() back for refilling (and its entries for adding).
  void release();
  /// The summary's entries of `out`, the commands of a line of the batch acquire() returned,
  /// added up later (in order) by the reader thread.
  void defer(const std::vector<Canon>& out);

 private:
  void produce();
  void fill(Batch& b);
  /// Reader thread: adds up the entries of the batches handed back, in order.
  void settle_returned();
  /// Interpreter's thread: adds up the entries of taken_ once every batch handed back before
  /// it is added up (by the reader, or here when it has stopped).
  void settle_taken();
  void settle(Batch& b);

  LineParser front_;
  const AxisLayout* import_axes_;
  unsigned import_axis_bits_;  ///< program_axis_bits(*import_axes_)
  MoveTally* tally_;
  BatchRing<Batch, kBatches> ring_;
  Batch* taken_ = nullptr;  ///< the consumer's batch between acquire() and release()
  // The batches handed back whose entries are not added up yet, oldest first (tally_ only).
  std::mutex returned_mutex_;
  std::condition_variable returned_cv_;
  std::array<Batch*, kBatches> returned_{};
  std::size_t returned_first_ = 0, returned_count_ = 0;
  bool reader_done_ = false;  ///< the reader thread adds nothing more
  std::thread thread_;        ///< last: starts once everything above is constructed
};

}  // namespace gm
