#pragma once
// Private to optimize/: the algorithms' NLopt names and properties, and NLopt's result codes
// in words (nlopt_algorithms.cc). optimizer.h stays free of nlopt.hpp.
#include <nlopt.hpp>

#include <string>

#include "optimize/optimizer.h"

namespace poise::optimize {

nlopt::algorithm nlopt_algorithm(Algorithm a);
/// DIRECT-L and ISRES search the whole box; the others are local.
bool is_global(Algorithm a);
/// COBYLA and ISRES take nonlinear inequality constraints; the others go through AUGLAG.
bool has_native_constraints(Algorithm a);
/// How NLopt stopped, in words with its result code's name.
std::string result_words(nlopt::result r);
/// Throws poise::Error for a value outside the table.
void check_algorithm(Algorithm a);

}  // namespace poise::optimize
