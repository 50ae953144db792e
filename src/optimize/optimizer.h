#pragma once
/// Derivative-free minimization of a black-box problem over bounded continuous variables,
/// on top of NLopt (COBYLA, BOBYQA, Sbplx, Nelder-Mead, DIRECT-L, ISRES).
///
///   * Variables are scaled to [0, 1] internally, so xtol_rel and the initial step (0.1 of the
///     range for the local methods) mean the same thing for a variable in mm and one in rpm.
///   * Constraints are values c_i(x) with c_i <= 0 meaning satisfied. COBYLA and ISRES take
///     them natively; BOBYQA, Sbplx, Nelder-Mead and DIRECT-L run inside NLopt's augmented
///     Lagrangian (LN_AUGLAG, or AUGLAG for DIRECT-L) with the chosen method as the subsidiary
///     optimizer. DIRECT-L inside AUGLAG is slow: every subproblem restarts the global search
///     of the whole box (each gets a tenth of max_evaluations).
///   * The problem is called once per distinct point (objective and constraints come from one
///     call; points revisited, e.g. by AUGLAG's subproblems, come from a cache) and at most
///     Options::max_evaluations times in total, also through AUGLAG.
///   * A failed evaluation (ok = false, non-finite objective or constraint) is recorded and
///     seen by the algorithm as a very bad point (objective and constraints 1e30); the search
///     continues. That is a wall for the local methods: when the start is next to a failing
///     region COBYLA can stall on its edge (BOBYQA, Sbplx, Nelder-Mead coped in the tests).
///   * The result is the best FEASIBLE evaluation of the history, not NLopt's last point.
///     If no evaluation was feasible, Result::feasible is false and minimize does not throw:
///     callers must check Result::feasible before using Result::x.
///   * Deterministic: the same inputs give the same history. ISRES draws from NLopt's global
///     random generator, seeded with Options::seed at each call (so concurrent ISRES runs in
///     several threads are not reproducible; run them one at a time).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace poise::optimize {

enum class Algorithm { kCobyla, kBobyqa, kSbplx, kNelderMead, kDirectL, kIsres };

/// "cobyla", "bobyqa", "sbplx", "neldermead", "direct_l", "isres" (case-insensitive).
/// Throws poise::Error listing the accepted names.
Algorithm parse_algorithm(std::string_view name);
/// The name parse_algorithm accepts ("direct_l" for kDirectL).
std::string to_string(Algorithm algorithm);
/// One line on which problems the algorithm suits.
std::string algorithm_advice(Algorithm algorithm);

/// A continuous, bounded variable: lower < upper, lower <= start <= upper, all finite.
struct Variable {
  std::string name;
  double lower = 0.0;
  double upper = 1.0;
  double start = 0.0;  ///< ignored by DIRECT-L (it starts from the centre of the box)
};

/// What the problem returns for one point.
struct Evaluation {
  double objective = NAN;
  std::vector<double> constraints;  ///< Options::constraints values; feasible iff every c <= 0
  bool ok = true;                   ///< false: the evaluation failed (a simulation diverged, ...)
  std::string message;              ///< why it failed (free text, kept in the history)
};

/// The black box: x in the variables' own units, in the order of the Variable list.
/// An exception thrown by the problem stops the search and propagates out of minimize.
using Problem = std::function<Evaluation(const std::vector<double>& x)>;

struct Options {
  Algorithm algorithm = Algorithm::kCobyla;
  /// Total calls of the problem (>= 1), also through AUGLAG. The global methods normally stop
  /// here (they have no convergence test but xtol_rel).
  int max_evaluations = 100;
  /// Stop when a step moves every variable by less than this fraction of its range
  /// (applied in the scaled [0, 1] space, as NLopt's xtol_rel and xtol_abs).
  double xtol_rel = 1e-4;
  /// NLopt's ftol_rel on the objective; local methods and AUGLAG's outer loop only (DIRECT-L
  /// would stop at the first plateau of its global search; the global methods run to
  /// max_evaluations or xtol_rel).
  double ftol_rel = 1e-8;
  std::size_t constraints = 0;  ///< number of constraint values the problem returns
  std::uint64_t seed = 1;       ///< ISRES only (nlopt::srand)
  /// A point is feasible iff ok and every constraint <= constraint_tolerance; also the
  /// tolerance given to NLopt for each constraint.
  double constraint_tolerance = 1e-8;
};

struct HistoryEntry {
  int evaluation = 0;  ///< 1-based call number
  std::vector<double> x;
  /// As returned by the problem, except that an ok evaluation with a non-finite objective or
  /// constraint is marked ok = false with a message saying so.
  Evaluation result;
  bool feasible = false;
};

struct Result {
  /// The best feasible point. If none was feasible: the ok point with the smallest largest
  /// constraint violation (for diagnosis only), or empty if every evaluation failed.
  std::vector<double> x;
  Evaluation best;        ///< the evaluation at x (default-constructed if x is empty)
  bool feasible = false;  ///< false: no feasible evaluation; do NOT use x as an optimum
  int evaluations = 0;    ///< calls of the problem (== history.size())
  /// How NLopt stopped, in words (e.g. "converged: xtol_rel reached (NLOPT_XTOL_REACHED)");
  /// prefixed with "no feasible evaluation ..." when feasible is false.
  std::string status;
  std::vector<HistoryEntry> history;
};

/// Minimizes the problem's objective over the variables' box subject to its constraints.
/// Throws poise::Error for bad variables (naming the variable) or options, and if the problem
/// returns a number of constraints other than Options::constraints. Does not throw when no
/// feasible point is found (see Result::feasible).
Result minimize(const Problem& f, const std::vector<Variable>& vars, const Options& opt);

}  // namespace poise::optimize
