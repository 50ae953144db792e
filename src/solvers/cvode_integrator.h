#pragma once
/// A CVODE integrator (SUNDIALS 6.4) owned by one worker thread: context, state vector,
/// dense matrix and linear solver (Eigen LU up to 16 states, small_dense_linear_solver.h;
/// SUNLinSol_Dense above) are created once and re-initialized per solve
/// (CVodeReInit), so nothing is allocated per sample.
///
/// Why CVODE (BDF, Newton, dense direct solver) and not IDA: the disk rotor's mass matrix
/// is 3x3 and inverted in closed form inside the right-hand side (models/disk_rotor.h),
/// so the system is an explicit ODE; it is stiff (support modes of ~100 Hz and a tanh
/// friction law against a 0.25 Hz oscillation), which BDF handles with large steps.
///
/// The right-hand side is a plain function that must not throw: it returns 0 on success,
/// > 0 for a recoverable failure (CVODE retries with a smaller step), < 0 to stop.
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace poise::solvers {

using RhsFunction = int (*)(double t, const double* y, double* ydot, void* user_data);

/// Relative tolerances CVODE can meet. Below ~100 x the double's unit roundoff (2.2e-16) it
/// cannot reach the accuracy asked and every integration fails ("tolerance too small"); above
/// 0.1 the error control no longer keeps the solution a solution.
inline constexpr double kMinRelativeTolerance = 1e-13;
inline constexpr double kMaxRelativeTolerance = 0.1;
/// "" if `rtol` is one CVODE can meet, else what is expected (for a model file's solver.rtol).
inline const char* relative_tolerance_problem(double rtol) {
  return rtol >= kMinRelativeTolerance && rtol <= kMaxRelativeTolerance
             ? ""
             : "a relative tolerance CVODE can meet, 1e-13 <= rtol <= 0.1 (tighter than ~100 x the "
               "double's 2.2e-16 every sample fails)";
}

struct CvodeOptions {
  double rtol = 1e-7;
  double atol = 1e-10;                 ///< absolute tolerance, same for every component...
  std::vector<double> atol_per_state;  ///< ...unless given per component (size n)
  double max_step = 0.0;               ///< 0 = no limit
  long max_steps = 100000;             ///< per call of advance()
  /// Highest BDF order (1-5). BDF orders above 2 are not A-stable: a lightly damped fast
  /// mode (the disk's supports) forces them into tiny steps, while BDF2 damps it and steps
  /// with the slow motion. 0 = CVODE's default (5).
  int max_order = 0;
};

/// Counters since the last reset() (CVodeReInit zeroes CVODE's counters).
struct CvodeStats {
  long steps = 0;
  long rhs_evals = 0;  ///< including those for finite-difference Jacobians
  long jac_evals = 0;
};

class CvodeIntegrator {
 public:
  CvodeIntegrator(std::size_t n, RhsFunction rhs, void* user_data, const CvodeOptions& opt = {});
  ~CvodeIntegrator();
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  /// Starts a new solve at t0 from y0 (re-initialization, no allocation).
  void reset(double t0, std::span<const double> y0);
  /// Takes internal steps until t >= t_out or one step if `one_step`; never steps past
  /// `t_stop`. Returns the time reached. Throws poise::Error with CVODE's message on failure.
  double advance(double t_out, double t_stop, bool one_step);
  /// Solution at t within the last step (CVodeGetDky, order-k interpolation).
  void interpolate(double t, std::span<double> y) const;
  /// The last step's interpolant as a Taylor polynomial about the solver's internal time
  /// tn: y(t) = sum_{j=0..q} c[j*n + i] (t - tn)^j, valid on [tn - h, tn]. `c` holds 6 n.
  int step_polynomial(std::span<double> c, double* tn) const;
  /// Current state (after the last step).
  std::span<const double> state() const;
  double time() const { return t_; }
  CvodeStats stats() const;
  std::size_t size() const { return n_; }

 private:
  /// Owns every SUNDIALS handle (freed in the right order, also when the constructor throws
  /// half-way): the one place each is held.
  struct Handles;  // complete in the .cc, where the constructor and destructor are
  std::size_t n_;
  std::unique_ptr<Handles> owned_;
  double t_ = 0.0;
  CvodeOptions opt_;
  mutable std::string last_error_;
  friend void cvode_error_handler(int, const char*, const char*, char*, void*);
};

}  // namespace poise::solvers
