#pragma once
/// A procedure run's samples on resume (procedure_runner.cc): the rows an interrupted run left in
/// samples.csv, and the solver counters run.json kept for them.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/procedure_study.h"

namespace poise::engine {

/// Samples already in an interrupted run's samples.csv (their outputs, status, solver steps
/// and failure reasons): complete lines only, in order from 0; a partial last line is cut off
/// the file. Throws if the header is not this study's.
std::vector<SampleResult> read_done_samples(const std::string& csv_path, const std::string& header,
                                            std::size_t n_inputs, std::size_t n_outputs, bool solver_steps);

/// A resumed run's samples come back from samples.csv with their solver steps but not their
/// right-hand-side evaluations: those the interrupted part recorded in run.json are added to
/// `mc`. Returns how many of the `resumed` samples have none recorded (a run killed before it
/// could write run.json), 0 when the count is whole.
std::size_t add_resumed_counters(const nlohmann::json& manifest, std::size_t resumed, McResult& mc);

}  // namespace poise::engine
