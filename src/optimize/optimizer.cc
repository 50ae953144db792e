#include "optimize/optimizer.h"

#include "core/number_text.h"

#include <nlopt.hpp>

#include <algorithm>
#include <exception>
#include <limits>
#include <map>
#include <new>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "optimize/nlopt_algorithms.h"

namespace poise::optimize {
namespace {

/// What the algorithms see for a failed evaluation (objective and every constraint), and after
/// the evaluation cap was reached (the search is being stopped then).
constexpr double kBad = 1e30;

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

void validate(const std::vector<Variable>& vars, const Options& opt) {
  require(!vars.empty(), "optimizer: at least one variable is required");
  for (std::size_t i = 0; i < vars.size(); ++i) {
    const Variable& v = vars[i];
    const std::string who = "optimizer variable '" + v.name + "' (#" + std::to_string(i + 1) + ")";
    require(std::isfinite(v.lower) && std::isfinite(v.upper) && std::isfinite(v.start),
            who + ": lower, upper and start must be finite (lower = " + number(v.lower) +
                ", upper = " + number(v.upper) + ", start = " + number(v.start) + ")");
    require(v.lower < v.upper, who + ": lower (" + number(v.lower) + ") must be below upper (" + number(v.upper) + ")");
    require(v.start >= v.lower && v.start <= v.upper,
            who + ": start " + number(v.start) + " is outside [" + number(v.lower) + ", " + number(v.upper) + "]");
    for (std::size_t j = 0; j < i; ++j) {
      require(vars[j].name != v.name || v.name.empty(), "optimizer: variable name '" + v.name + "' appears twice");
    }
  }
  require(opt.max_evaluations >= 1,
          "optimizer: max_evaluations must be at least 1 (got " + std::to_string(opt.max_evaluations) + ")");
  require(std::isfinite(opt.xtol_rel) && opt.xtol_rel >= 0.0,
          "optimizer: xtol_rel must be finite and >= 0 (got " + number(opt.xtol_rel) + ")");
  require(std::isfinite(opt.ftol_rel) && opt.ftol_rel >= 0.0,
          "optimizer: ftol_rel must be finite and >= 0 (got " + number(opt.ftol_rel) + ")");
  require(std::isfinite(opt.constraint_tolerance) && opt.constraint_tolerance >= 0.0,
          "optimizer: constraint_tolerance must be finite and >= 0 (got " + number(opt.constraint_tolerance) + ")");
  check_algorithm(opt.algorithm);
}

/// State of one minimize call, shared by the NLopt callbacks (all in scaled coordinates u).
class Run {
 public:
  Run(const Problem& f, const std::vector<Variable>& vars, const Options& opt) : f_(f), vars_(vars), opt_(opt) {}

  void set_stopper(nlopt::opt* o) { stopper_ = o; }

  /// Makes history_[current_] the evaluation at u, calling the problem only for a point not
  /// evaluated before (the objective and every constraint at one point, and the points that
  /// AUGLAG's subproblems or DIRECT revisit, cost one call). Returns false if the search must
  /// stop (the cap is reached or the problem threw).
  bool evaluate(unsigned n, const double* u) {
    if (stopping_) return false;
    if (!history_.empty() && std::equal(u, u + n, seen_key(current_).begin())) return true;
    std::vector<double> key(u, u + n);
    if (const auto it = seen_.find(key); it != seen_.end()) {
      current_ = it->second;
      return true;
    }
    if (history_.size() >= static_cast<std::size_t>(opt_.max_evaluations)) {
      cap_reached_ = true;
      stop();
      return false;
    }
    std::vector<double> x(n);
    for (unsigned i = 0; i < n; ++i) {
      const Variable& v = vars_[i];
      x[i] = std::clamp(v.lower + u[i] * (v.upper - v.lower), v.lower, v.upper);
    }
    Evaluation e;
    try {
      e = f_(x);
      if (e.ok && e.constraints.size() != opt_.constraints) {
        throw Error("optimizer: the problem returned " + std::to_string(e.constraints.size()) +
                    " constraint values, Options::constraints is " + std::to_string(opt_.constraints));
      }
    } catch (...) {
      error_ = std::current_exception();
      stop();
      return false;
    }
    if (e.ok && !std::isfinite(e.objective)) {
      e.ok = false;
      e.message = "objective is not finite (" + number(e.objective) + ")";
    }
    for (std::size_t i = 0; e.ok && i < e.constraints.size(); ++i) {
      if (!std::isfinite(e.constraints[i])) {
        e.ok = false;
        e.message = "constraint " + std::to_string(i + 1) + " is not finite (" + number(e.constraints[i]) + ")";
      }
    }
    bool feasible = e.ok;
    for (double c : e.constraints) feasible = feasible && c <= opt_.constraint_tolerance;
    history_.push_back(HistoryEntry{static_cast<int>(history_.size()) + 1, std::move(x), std::move(e), feasible});
    current_ = history_.size() - 1;
    keys_.emplace_back(seen_.emplace(std::move(key), current_).first);
    return true;
  }

  double objective(unsigned n, const double* u) {
    if (!evaluate(n, u)) return kBad;
    const Evaluation& e = history_[current_].result;
    return e.ok ? e.objective : kBad;
  }

  double constraint(std::size_t i, unsigned n, const double* u) {
    if (!evaluate(n, u)) return kBad;
    const Evaluation& e = history_[current_].result;
    return e.ok ? e.constraints[i] : kBad;
  }

  bool cap_reached() const { return cap_reached_; }
  const std::exception_ptr& error() const { return error_; }
  std::vector<HistoryEntry>& history() { return history_; }

 private:
  const std::vector<double>& seen_key(std::size_t i) const { return keys_[i]->first; }

  void stop() {
    stopping_ = true;
    if (stopper_ != nullptr) stopper_->force_stop();  // also stops AUGLAG's subsidiary
  }

  const Problem& f_;
  const std::vector<Variable>& vars_;
  const Options& opt_;
  nlopt::opt* stopper_ = nullptr;
  using Seen = std::map<std::vector<double>, std::size_t>;  // scaled point -> history index
  Seen seen_;
  std::vector<Seen::const_iterator> keys_;  // history index -> its entry in seen_
  std::size_t current_ = 0;
  std::vector<HistoryEntry> history_;
  bool stopping_ = false;
  bool cap_reached_ = false;
  std::exception_ptr error_;
};

struct ConstraintData {
  Run* run;
  std::size_t index;
};

double objective_callback(unsigned n, const double* u, double* /*grad*/, void* data) {
  return static_cast<Run*>(data)->objective(n, u);
}

double constraint_callback(unsigned n, const double* u, double* /*grad*/, void* data) {
  auto* d = static_cast<ConstraintData*>(data);
  return d->run->constraint(d->index, n, u);
}

/// NLopt's own evaluation limit. NLopt counts calls of the objective callback, including the
/// points Run serves from its cache, so it is only a safety bound: Run counts the calls of the
/// problem and force-stops at max_evaluations.
int nlopt_maxeval(const Options& opt) {
  constexpr int kMax = std::numeric_limits<int>::max() / 16;
  return std::min(opt.max_evaluations, kMax) * 10 + 100;
}

/// Bounds [0, 1], tolerances, evaluation limit and, for the local methods, ftol_rel and the
/// initial step (the global ones keep NLopt's defaults; DIRECT-L would stop on ftol_rel at the
/// first plateau of its global search).
void configure(nlopt::opt& o, unsigned n, const Options& opt, bool local) {
  o.set_lower_bounds(std::vector<double>(n, 0.0));
  o.set_upper_bounds(std::vector<double>(n, 1.0));
  o.set_xtol_rel(opt.xtol_rel);
  o.set_xtol_abs(opt.xtol_rel);  // the range is 1: "fraction of the range" also near u = 0
  o.set_maxeval(nlopt_maxeval(opt));
  if (local) {
    o.set_ftol_rel(opt.ftol_rel);
    o.set_initial_step(0.1);
  }
}

/// Index of the best feasible entry, or of the ok entry with the smallest largest violation
/// if none is feasible; history.size() if every evaluation failed.
std::size_t pick_best(const std::vector<HistoryEntry>& history, bool& feasible) {
  std::size_t best = history.size();
  feasible = false;
  for (std::size_t i = 0; i < history.size(); ++i) {
    const HistoryEntry& h = history[i];
    if (h.feasible && (!feasible || h.result.objective < history[best].result.objective)) {
      best = i;
      feasible = true;
    }
  }
  if (feasible) return best;
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < history.size(); ++i) {
    const HistoryEntry& h = history[i];
    if (!h.result.ok) continue;
    double violation = 0.0;
    for (double c : h.result.constraints) violation = std::max(violation, c);
    if (violation < least) {
      least = violation;
      best = i;
    }
  }
  return best;
}

// AUGLAG's outer iterations, with the chosen algorithm as its subsidiary.
void set_auglag_subsidiary(nlopt::opt& o, unsigned n, const Options& opt, bool local) {
  o.set_ftol_rel(opt.ftol_rel);  // AUGLAG's outer iterations, also around DIRECT-L
  // The subsidiary's limits apply per subproblem; Run counts the total and force-stops.
  // DIRECT-L does not converge by itself: with the whole budget per subproblem the first one
  // (weakest penalty) spends every evaluation. A tenth of the total per subproblem: on
  // min x + y s.t. x y >= 1/2, max_evaluations = 1000 ends at f* + 2e-4 after 326 calls
  // (3000: f* + 2e-6), against f* + 7e-2 after 3000 calls with the whole budget.
  nlopt::opt sub(nlopt_algorithm(opt.algorithm), n);
  configure(sub, n, opt, local);
  if (!local) sub.set_maxeval(std::max(1, opt.max_evaluations / 10));
  o.set_local_optimizer(sub);
}

// The start point in [0, 1]^n (each variable's fraction of its range).
std::vector<double> start_point(const std::vector<Variable>& vars) {
  std::vector<double> u(vars.size());
  for (std::size_t i = 0; i < vars.size(); ++i) {
    const Variable& v = vars[i];
    u[i] = std::clamp((v.start - v.lower) / (v.upper - v.lower), 0.0, 1.0);
  }
  return u;
}

// Runs NLopt from u: how it stopped, in words. An error of the problem is rethrown.
std::string optimize_status(nlopt::opt& o, Run& run, std::vector<double>& u, const Options& opt) {
  std::string status;
  try {
    double fu = 0.0;
    status = result_words(o.optimize(u, fu));
  } catch (const nlopt::roundoff_limited&) {
    status =
        "stopped: roundoff limited, no further progress at floating-point precision "
        "(NLOPT_ROUNDOFF_LIMITED)";
  } catch (const nlopt::forced_stop&) {
    if (run.error()) std::rethrow_exception(run.error());
    status = run.cap_reached() ? "stopped: max_evaluations (" + std::to_string(opt.max_evaluations) +
                                     ") calls of the problem reached (NLOPT_FORCED_STOP)"
                               : std::string("stopped: forced stop (NLOPT_FORCED_STOP)");
  } catch (const std::invalid_argument& e) {
    throw Error("optimizer: NLopt refused the setup of " + to_string(opt.algorithm) + ": " + e.what());
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::runtime_error& e) {
    if (run.error()) std::rethrow_exception(run.error());
    status = std::string("stopped: NLopt failure: ") + e.what() + " (NLOPT_FAILURE)";
  }
  if (run.error()) std::rethrow_exception(run.error());
  return status;
}

// The history, the best (or least violating) point and the status.
Result collect_result(Run& run, std::string status, const Options& opt) {
  Result result;
  result.history = std::move(run.history());
  result.evaluations = static_cast<int>(result.history.size());
  const std::size_t best = pick_best(result.history, result.feasible);
  if (best < result.history.size()) {
    result.x = result.history[best].x;
    result.best = result.history[best].result;
  }
  if (!result.feasible) {
    std::string why = "no feasible evaluation in " + std::to_string(result.evaluations) + " evaluations";
    if (result.x.empty()) {
      why += " (every evaluation failed)";
    } else {
      double violation = 0.0;
      for (double c : result.best.constraints) violation = std::max(violation, c);
      why += " (x is the least violating point, largest constraint " + short_number(violation) + " > tolerance " +
             short_number(opt.constraint_tolerance) + ")";
    }
    status = why + "; " + status;
  }
  result.status = std::move(status);
  return result;
}

}  // namespace

Result minimize(const Problem& f, const std::vector<Variable>& vars, const Options& opt) {
  validate(vars, opt);
  require(static_cast<bool>(f), "optimizer: the problem function is empty");
  const auto n = static_cast<unsigned>(vars.size());
  const bool local = !is_global(opt.algorithm);
  const bool auglag = opt.constraints > 0 && !has_native_constraints(opt.algorithm);

  Run run(f, vars, opt);
  nlopt::opt o(auglag ? (local ? nlopt::LN_AUGLAG : nlopt::AUGLAG) : nlopt_algorithm(opt.algorithm), n);
  configure(o, n, opt, local);
  if (auglag) set_auglag_subsidiary(o, n, opt, local);
  run.set_stopper(&o);
  o.set_min_objective(objective_callback, &run);
  std::vector<ConstraintData> constraint_data(opt.constraints);
  for (std::size_t i = 0; i < opt.constraints; ++i) {
    constraint_data[i] = ConstraintData{&run, i};
    o.add_inequality_constraint(constraint_callback, &constraint_data[i], opt.constraint_tolerance);
  }
  if (opt.algorithm == Algorithm::kIsres) nlopt::srand(static_cast<unsigned long>(opt.seed));

  std::vector<double> u = start_point(vars);
  std::string status = optimize_status(o, run, u, opt);
  return collect_result(run, std::move(status), opt);
}

}  // namespace poise::optimize
