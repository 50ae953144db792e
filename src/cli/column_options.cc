#include "cli/column_options.h"

#include "core/format.h"

namespace poise::cli {

void add_column_options(CLI::App* command, ColumnOptions& options, const std::vector<estimators::ColumnRole>& roles) {
  std::string listed;
  for (const auto& r : roles) {
    listed += fmt::format("{}{} (default '{}', {}{})", listed.empty() ? "" : ", ", r.role,
                          r.default_headers.empty() ? std::string() : r.default_headers.front(), r.default_unit,
                          r.required ? "" : ", optional");
  }
  command
      ->add_option("--column", options.columns,
                   "ROLE=HEADER: the file's column that holds ROLE, e.g. --column current=Iq (repeatable). "
                   "Roles: " +
                       listed)
      ->type_name("ROLE=HEADER");
  command
      ->add_option("--unit", options.units,
                   "ROLE=UNIT: the unit of that column, any unit Poise knows of its kind (ms, mA, rad, rev), "
                   "or one count as a quantity or fraction (--unit angle=\"1/16384 rev\"); without it, the "
                   "unit in the header (\"time [ms]\", \"Iq (A)\", \"position_rad\"); a default header (time_s, ...) "
                   "has its default unit, any other header needs one of these")
      ->type_name("ROLE=UNIT");
}

estimators::ColumnMapping column_mapping(const ColumnOptions& options,
                                         const std::vector<estimators::ColumnRole>& roles) {
  estimators::ColumnMapping mapping;
  for (const auto& c : options.columns) estimators::add_column_option(mapping, "--column", c, roles);
  for (const auto& u : options.units) estimators::add_column_option(mapping, "--unit", u, roles);
  return mapping;
}

}  // namespace poise::cli
