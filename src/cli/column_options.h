#pragma once
/// --column ROLE=HEADER and --unit ROLE=UNIT of the commands that read a lab's file
/// (diagnose-record, fit, diagnose): how a file's own columns and units are named on the
/// command line (estimators/lab_table.h reads them).
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "estimators/lab_table.h"

namespace poise::cli {

struct ColumnOptions {
  std::vector<std::string> columns;  ///< ROLE=HEADER
  std::vector<std::string> units;    ///< ROLE=UNIT
};

/// Adds the two repeatable options to a command, their help listing the roles with their
/// default headers and units.
void add_column_options(CLI::App* command, ColumnOptions& options, const std::vector<estimators::ColumnRole>& roles);

/// The mapping the options give; throws poise::InputError naming the option for a malformed one.
estimators::ColumnMapping column_mapping(const ColumnOptions& options,
                                         const std::vector<estimators::ColumnRole>& roles);

}  // namespace poise::cli
