// The run settings' table bound to CLI11 options (flag name, help, check from each row).
#include "cli/settings_flags.hpp"

#include <map>
#include <string>

namespace gm::cli {

void add_setting_flags(CLI::App* sub, setup::RunSettings& settings, unsigned groups) {
  std::map<std::string, CLI::Option*> added;
  for (const setup::SettingRow& row : setup::setting_rows()) {
    if ((row.groups & groups) == 0) continue;
    CLI::Option* opt = std::visit(
        [&](auto member) -> CLI::Option* {
          auto& field = settings.*member;
          if constexpr (std::is_same_v<std::remove_reference_t<decltype(field)>, bool>)
            return sub->add_flag(row.flag, field, row.help);
          else
            return sub->add_option(row.flag, field, row.help);
        },
        row.field);
    if (row.check == setup::SettingCheck::Positive) opt->check(CLI::PositiveNumber);
    if (row.check == setup::SettingCheck::OneOf) {
      if (row.ignore_case)
        opt->check(CLI::IsMember(row.choices, CLI::ignore_case));
      else
        opt->check(CLI::IsMember(row.choices));
    }
    added[row.flag] = opt;
  }
  for (const setup::SettingRow& row : setup::setting_rows())
    if (!row.excludes.empty() && added.count(row.flag) > 0 && added.count(row.excludes) > 0)
      added[row.flag]->excludes(added[row.excludes]);
}

}  // namespace gm::cli
