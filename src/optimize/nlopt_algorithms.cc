#include "optimize/nlopt_algorithms.h"

#include <cctype>
#include <string_view>

#include "core/error.h"

namespace poise::optimize {
namespace {

struct AlgorithmInfo {
  Algorithm algorithm;
  const char* name;
  const char* advice;
};

constexpr AlgorithmInfo kAlgorithms[] = {
    {Algorithm::kCobyla, "cobyla",
     "COBYLA: local, derivative-free (linear models); native nonlinear inequality constraints; "
     "robust on non-smooth but noise-free objectives; slow final convergence"},
    {Algorithm::kBobyqa, "bobyqa",
     "BOBYQA: local, derivative-free (quadratic models); fastest on smooth objectives; bounds only, "
     "constraints via the augmented Lagrangian (AUGLAG); poor with noise or failed points"},
    {Algorithm::kSbplx, "sbplx",
     "Sbplx: local, derivative-free (Nelder-Mead on subspaces); tolerant of noise and "
     "non-smoothness, more evaluations than BOBYQA; constraints via AUGLAG"},
    {Algorithm::kNelderMead, "neldermead",
     "Nelder-Mead: local, derivative-free simplex; simple and robust for a few non-smooth variables, "
     "may stall in higher dimensions (prefer Sbplx); constraints via AUGLAG"},
    {Algorithm::kDirectL, "direct_l",
     "DIRECT-L: global, deterministic box division; bounded boxes with few variables (<= ~5) and "
     "cheap evaluations; ignores the start point; constraints via AUGLAG (slow)"},
    {Algorithm::kIsres, "isres",
     "ISRES: global, stochastic evolution strategy (seeded); native nonlinear constraints; "
     "needs many evaluations (thousands)"},
};

const AlgorithmInfo& info(Algorithm a) {
  for (const auto& i : kAlgorithms) {
    if (i.algorithm == a) return i;
  }
  throw Error("unknown optimization algorithm value " + std::to_string(static_cast<int>(a)));
}

}  // namespace

nlopt::algorithm nlopt_algorithm(Algorithm a) {
  switch (a) {
    case Algorithm::kCobyla: return nlopt::LN_COBYLA;
    case Algorithm::kBobyqa: return nlopt::LN_BOBYQA;
    case Algorithm::kSbplx: return nlopt::LN_SBPLX;
    case Algorithm::kNelderMead: return nlopt::LN_NELDERMEAD;
    case Algorithm::kDirectL: return nlopt::GN_DIRECT_L;
    case Algorithm::kIsres: return nlopt::GN_ISRES;
  }
  throw Error("unknown optimization algorithm value " + std::to_string(static_cast<int>(a)));
}

bool is_global(Algorithm a) { return a == Algorithm::kDirectL || a == Algorithm::kIsres; }
bool has_native_constraints(Algorithm a) { return a == Algorithm::kCobyla || a == Algorithm::kIsres; }

std::string result_words(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS: return "converged (NLOPT_SUCCESS)";
    case nlopt::STOPVAL_REACHED: return "converged: stopval reached (NLOPT_STOPVAL_REACHED)";
    case nlopt::FTOL_REACHED: return "converged: ftol_rel reached (NLOPT_FTOL_REACHED)";
    case nlopt::XTOL_REACHED: return "converged: xtol_rel reached (NLOPT_XTOL_REACHED)";
    case nlopt::MAXEVAL_REACHED: return "stopped: max_evaluations reached (NLOPT_MAXEVAL_REACHED)";
    case nlopt::MAXTIME_REACHED: return "stopped: time limit reached (NLOPT_MAXTIME_REACHED)";
    default: break;
  }
  return "NLopt result code " + std::to_string(static_cast<int>(r));
}

void check_algorithm(Algorithm a) { (void)info(a); }

Algorithm parse_algorithm(std::string_view name) {
  std::string lower(name);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string names;
  for (const auto& i : kAlgorithms) {
    if (lower == i.name) return i.algorithm;
    names += names.empty() ? "" : ", ";
    names += i.name;
  }
  throw Error("unknown optimization algorithm '" + std::string(name) + "': expected one of " + names);
}

std::string to_string(Algorithm algorithm) { return info(algorithm).name; }

std::string algorithm_advice(Algorithm algorithm) { return info(algorithm).advice; }

}  // namespace poise::optimize
