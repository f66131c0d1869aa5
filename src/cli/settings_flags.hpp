// The run settings' table bound to CLI11 options: every command's run flags come from it.
#pragma once

#include "setup/run_settings.hpp"

#include <CLI/CLI.hpp>

namespace gm::cli {

/// Adds one option (or switch) per row of setup::setting_rows() in `groups` to `sub`, bound to
/// its field of `settings`, with the row's help text and check.
void add_setting_flags(CLI::App* sub, setup::RunSettings& settings, unsigned groups);

}  // namespace gm::cli
