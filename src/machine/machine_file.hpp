// The TOML machine file: load, validate (errors name key, file and line) and write a Machine.
#pragma once

#include "machine/machine.hpp"

#include <filesystem>
#include <string>
#include <string_view>

namespace gm {

/// Reads and validates a machine file (a `.ini` is read as a LinuxCNC INI: linuxcnc_ini.hpp).
/// Throws gm::InputError with a located message "FILE:LINE: key 'axes.x.blu_mm': must be > 0 (got
/// -1)" for a TOML syntax error, a missing required key, a mistyped value, an unknown key or an
/// out-of-range value.
Machine load_machine_file(const std::filesystem::path& path);

/// Parses machine TOML text; source_name is used in messages and stored in Machine::source.
Machine parse_machine_toml(std::string_view text, std::string_view source_name);

/// Writes a complete machine file (every key) that parse_machine_toml reads back to an equal
/// Machine (doubles are written with round-trip precision).
std::string machine_to_toml(const Machine& m);

}  // namespace gm
