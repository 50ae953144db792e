#pragma once
/// `poise error-mechanisms [DIR] [--calibrate TABLE] [--json]`: which per-test error mechanism
/// do measured static-unbalance tests support? Likelihood of scale-and-zero (K_T scale and
/// gimbal-zero error per test) against an additive error on the unbalance vector, calibrated
/// on one table and validated on the others (estimators/error_mechanism_likelihood.h).
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/unbalance_test_tables.h"

namespace poise::cli {

/// The whole comparison as JSON (what --json prints): `position_noise` in N*m, `calibrate` the
/// table the mechanisms are calibrated on ("" = none: joint fits and checks only), `draws`
/// simulated copies per predictive check.
nlohmann::json compare_error_mechanisms(const UnbalanceTestData& data, double position_noise,
                                        const std::string& calibrate, int draws);

/// The comparison of a folder of measured tables (tables2_3_loading_tests.csv,
/// tables4_5_repeatability.csv, and table1_loading_test_36pt.csv for the position noise), as
/// `poise error-mechanisms DIR --json` prints it. Throws UsageError for a `calibrate` table the
/// folder lacks, poise::Error for a file it refuses.
nlohmann::json compare_error_mechanisms_in(const std::string& dir, const std::string& calibrate, int draws);

using ErrorMechanismsHandler = std::function<std::optional<int>()>;
ErrorMechanismsHandler add_error_mechanisms_command(CLI::App& app);

}  // namespace poise::cli
