// gmotion moves PROGRAM: the canonical moves as JSON Lines (mm, mm/min, machine coordinates).
#include "cli/commands.hpp"
#include "cli/language_flags.hpp"
#include "cli/run_setup.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"
#include "machine/machine_file.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>
#include <string_view>

namespace gm::cli {

namespace {

const char* plane_name(Plane p) {
  return p == Plane::XY ? "XY" : p == Plane::XZ ? "XZ" : "YZ";
}

// One JSON object per canonical move. Numbers are printed shortest-round-trip ({} in fmt).
// Rapids print "feed":0 (the machine's rapid rate applies; it is not part of the program).
void print_move(std::FILE* f, const Canon& c, const AxisLayout& axes) {
  if (const auto* m = std::get_if<Motion>(&c)) {
    const char* kind = m->kind == MotionKind::Rapid  ? "rapid"
                       : m->kind == MotionKind::Line ? "line"
                                                     : "arc";
    fmt::print(f, "{{\"line\":{},\"kind\":\"{}\",\"end\":[{},{},{}],\"feed\":{}", m->line, kind,
               m->end_mm[0] + 0.0, m->end_mm[1] + 0.0, m->end_mm[2] + 0.0,
               m->kind == MotionKind::Rapid ? 0.0 : m->feed_mm_min);
    // The machine's axes past X, Y, Z: "axes":{"A":90,...} (degrees for A, B, C).
    if (!axes.is_xyz()) {
      std::string more;
      for (int a = 0; a < axes.count; ++a)
        if (axes.program(a) >= 3)
          more += fmt::format("{}\"{}\":{}", more.empty() ? "" : ",", axes.letter(a),
                              m->end_mm[axes.program(a)] + 0.0);
      if (!more.empty()) fmt::print(f, ",\"axes\":{{{}}}", more);
    }
    if (m->kind == MotionKind::Arc)
      fmt::print(f, ",\"center\":[{},{},{}],\"dir\":\"{}\",\"turns\":{},\"plane\":\"{}\"",
                 m->center_mm[0] + 0.0, m->center_mm[1] + 0.0, m->center_mm[2] + 0.0,
                 m->ccw ? "ccw" : "cw", m->turns, plane_name(m->plane));
    fmt::print(f, "}}\n");
  } else if (const auto* d = std::get_if<Dwell>(&c)) {
    fmt::print(f, "{{\"line\":{},\"kind\":\"dwell\",\"seconds\":{}}}\n", d->line, d->seconds);
  }
}

// A JSON string literal of `text` (quotes, backslashes and control characters escaped).
std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (u < 0x20) {
      out += fmt::format("\\u{:04x}", u);
    } else {
      out += ch;
    }
  }
  return out + '"';
}

// --messages: (MSG,...), (DEBUG,...) and (PRINT,...) texts as records of kind "message".
void print_message(std::FILE* f, const Canon& c) {
  if (const auto* e = std::get_if<Event>(&c); e && e->kind == EventKind::Message)
    fmt::print(f, "{{\"line\":{},\"kind\":\"message\",\"text\":{}}}\n", e->line,
               json_string(e->text));
}

}  // namespace

void add_moves(CLI::App& app, Context& ctx) {
  auto* sub = app.add_subcommand(
      "moves", "Print the canonical moves as JSON Lines (mm, mm/min, machine coordinates)");
  struct Opts {
    std::string program;
    std::string machine_file;
    std::string tool_table;
    std::string axes;
    bool block_delete = false;
    bool messages = false;
    LanguageFlags language;
  };
  auto opts = std::make_shared<Opts>();
  sub->add_option("PROGRAM", opts->program, "G-code file ('-' reads stdin)")->required();
  sub->add_option("--machine", opts->machine_file, "machine description file (TOML)");
  sub->add_option("--axes", opts->axes, kAxesFlagHelp);
  sub->add_option("--tool-table", opts->tool_table,
                  "LinuxCNC tool table (T1 P1 Z50 D6 ;comment), mm; default: the machine's");
  sub->add_flag("--block-delete", opts->block_delete, "skip lines that start with '/'");
  add_language_flags(sub, opts->language);
  sub->add_flag("--messages", opts->messages,
                "also print MSG/DEBUG/PRINT comments as records of kind \"message\"");
  sub->callback([opts, &ctx] {
    Machine machine;
    if (!opts->machine_file.empty()) machine = load_machine_file(opts->machine_file);
    apply_axes_flag(machine, opts->axes);
    if (!opts->tool_table.empty()) machine.tool_table = load_tool_table(opts->tool_table);
    InterpreterOptions io{&machine, opts->block_delete};
    apply_language_flags(opts->language, machine, io);
    const std::string name = opts->program == "-" ? "<stdin>" : opts->program;

    // Nothing is printed if the program has any error: check it whole first, then stream it
    // (stdin is spooled to an unlinked temporary file so it can be read twice without being held).
    ProgramInput program(opts->program);
    if (!validate_program(program, io)) {
      ctx.exit_code = static_cast<int>(ExitCode::InputError);
      return;
    }
    std::istream* in = &program.rewind();
    io.save_parameters = true;  // the parameter file is written once, after the real pass
    ProgramStream stream(*in, name, io);
    Canon c;
    while (stream.next(c)) {
      print_move(stdout, c, machine.layout);
      if (opts->messages) print_message(stdout, c);
    }
    std::fflush(stdout);
    ctx.exit_code = 0;
  });
}

}  // namespace gm::cli
