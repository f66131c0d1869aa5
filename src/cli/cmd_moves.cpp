// gmotion moves PROGRAM: the canonical moves as JSON Lines (mm, mm/min, machine coordinates).
#include "cli/commands.hpp"
#include "cli/settings_flags.hpp"
#include "common/status.hpp"
#include "interp/program.hpp"
#include "setup/program_input.hpp"

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
    const char* kind = motion_kind_name(*m);
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
    if (m->mm_per_rev > 0.0)  // G95/G33: "feed" is mm_per_rev x the spindle speed at the start
      fmt::print(f, ",\"mm_per_rev\":{}", m->mm_per_rev);
    if (m->by_operator) fmt::print(f, ",\"operator\":true");
    fmt::print(f, "}}\n");
  } else if (const auto* d = std::get_if<Dwell>(&c)) {
    fmt::print(f, "{{\"line\":{},\"kind\":\"{}\",\"seconds\":{}}}\n", d->line,
               d->pause ? "pause" : "dwell", d->seconds);
  }
}

// --io: spindle, coolant, tool, output, input, user M-code and program stop records (the schema
// is in docs/machine-codes.md, "Records of gmotion moves --io").
void print_io(std::FILE* f, const Canon& c) {
  const auto* e = std::get_if<Event>(&c);
  if (!e) return;
  const auto rec = [&](std::string_view kind, const std::string& fields) {
    fmt::print(f, "{{\"line\":{},\"kind\":\"{}\"{}{}}}\n", e->line, kind, fields.empty() ? "" : ",",
               fields);
  };
  const char* on = e->index != 0 ? "true" : "false";
  switch (e->kind) {
    case EventKind::SpindleSpeed:
      return rec("spindle_speed", fmt::format("\"rpm\":{}", e->value));
    case EventKind::SpindleStart:
      return rec("spindle",
                 fmt::format("\"dir\":\"{}\",\"rpm\":{}", e->index > 0 ? "cw" : "ccw", e->value));
    case EventKind::SpindleStop:
      return rec("spindle", "\"dir\":\"off\"");
    case EventKind::SpindleOrient:
      return rec("spindle_orient", fmt::format("\"angle\":{},\"mode\":{}", e->value, e->index));
    case EventKind::OrientWait:
      return rec("spindle_orient_wait", fmt::format("\"timeout\":{}", e->value));
    case EventKind::Mist:
      return rec("coolant", fmt::format("\"mist\":{}", on));
    case EventKind::Flood:
      return rec("coolant", fmt::format("\"flood\":{}", on));
    case EventKind::ToolSelect:
      return rec("tool_select", fmt::format("\"tool\":{}", e->index));
    case EventKind::ToolChange:
      return rec("tool_change", fmt::format("\"tool\":{}", e->index));
    case EventKind::ToolNumber:
      return rec("tool_number", fmt::format("\"tool\":{}", e->index));
    case EventKind::DigitalOut:
      return rec("digital_out", fmt::format("\"pin\":{},\"on\":{},\"sync\":{}", e->index,
                                            e->value != 0.0, e->sync));
    case EventKind::AnalogOut:
      return rec("analog_out", fmt::format("\"channel\":{},\"value\":{},\"sync\":{}", e->index,
                                           e->value, e->sync));
    case EventKind::WaitInput:
      return rec("wait_input", fmt::format("\"input\":{},\"analog\":{},\"mode\":{},\"timeout\":{}",
                                           e->index, e->analog, e->mode, e->value));
    case EventKind::UserMcode:
      return rec("user_mcode",
                 fmt::format("\"code\":{},\"p\":{},\"q\":{}", e->index, e->value, e->value2));
    case EventKind::Pause:
    case EventKind::OptionalPause:
    case EventKind::End:
      // M0, M1, M2, M30, M60; "%" for the closing percent line (no M code).
      return rec("stop", e->kind == EventKind::End && e->index == 0
                             ? std::string("\"code\":\"%\"")
                             : fmt::format("\"code\":\"M{}\"", e->index));
    case EventKind::OverrideEnable:
    case EventKind::OverrideDisable:
    case EventKind::Message:
      return;
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
    setup::RunSettings settings;  ///< the machine file, axes, tools, block delete, language
    bool messages = false;
    bool io = false;
  };
  auto opts = std::make_shared<Opts>();
  sub->add_option("PROGRAM", opts->program, "G-code file ('-' reads stdin)")->required();
  add_setting_flags(sub, opts->settings, setup::kProgramGroup | setup::kLanguageGroup);
  sub->add_flag("--messages", opts->messages,
                "also print MSG/DEBUG/PRINT comments as records of kind \"message\"");
  sub->add_flag("--io", opts->io,
                "also print spindle, coolant, tool, I/O, user M-code and stop records "
                "(docs/machine-codes.md)");
  sub->callback([opts, &ctx] {
    const Machine machine = setup::resolve_machine(opts->settings, setup::IniNotes::Quiet);
    InterpreterOptions io = setup::interpreter_options(opts->settings, machine);
    const std::string name = opts->program == "-" ? "<stdin>" : opts->program;

    // Nothing is printed if the program has any error: check it whole first, then stream it
    // (stdin is spooled to an unlinked temporary file so it can be read twice without being held).
    setup::ProgramInput program(opts->program);
    if (!setup::validate_program(program, io)) {
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
      if (opts->io) print_io(stdout, c);
    }
    std::fflush(stdout);
    ctx.exit_code = 0;
  });
}

}  // namespace gm::cli
