#include "solvers/cvode_integrator.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <memory>
#include <type_traits>

#include "core/error.h"
#include "solvers/serial_vector_norm.h"
#include "solvers/small_dense_linear_solver.h"

namespace poise::solvers {

// The right-hand side and its user data, handed to CVODE as user_data. Outside the anonymous
// namespace: CvodeIntegrator::Handles holds one, and a member of a type with internal linkage
// warns (-Wsubobject-linkage) where this file is compiled inside a unity batch.
struct CvodeRhsBinding {
  RhsFunction rhs;
  void* user;
};

namespace {

// The C callback: forwards raw arrays; the user function must not throw.
int cvode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
  auto* b = static_cast<CvodeRhsBinding*>(user_data);
  return b->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot), b->user);
}

void check(int flag, const char* what, const std::string& detail = "") {
  if (flag < 0) {
    throw Error(std::string("CVODE ") + what + " failed (flag " + std::to_string(flag) + ")" +
                (detail.empty() ? "" : ": " + detail));
  }
}

}  // namespace

struct CvodeIntegrator::Handles {
  struct FreeContext {
    void operator()(SUNContext c) const { SUNContext_Free(&c); }
  };
  struct FreeVector {
    void operator()(N_Vector v) const { N_VDestroy(v); }
  };
  struct FreeMatrix {
    void operator()(SUNMatrix m) const { SUNMatDestroy(m); }
  };
  struct FreeSolver {
    void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
  };
  struct FreeMemory {
    void operator()(void* m) const { CVodeFree(&m); }
  };
  // Destroyed in reverse order: the binding and CVODE's memory first, the context last.
  std::unique_ptr<std::remove_pointer_t<SUNContext>, FreeContext> context;
  std::unique_ptr<std::remove_pointer_t<N_Vector>, FreeVector> y, tmp;
  std::unique_ptr<std::remove_pointer_t<SUNMatrix>, FreeMatrix> matrix;
  std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, FreeSolver> solver;
  std::unique_ptr<void, FreeMemory> memory;
  std::unique_ptr<CvodeRhsBinding> binding;
};

// Keeps CVODE's message for the exception instead of printing it to stderr.
void cvode_error_handler(int, const char* module, const char* function, char* msg, void* data) {
  auto* self = static_cast<CvodeIntegrator*>(data);
  self->last_error_ = std::string(module) + "::" + function + ": " + msg;
}

CvodeIntegrator::CvodeIntegrator(std::size_t n, RhsFunction rhs, void* user_data, const CvodeOptions& opt)
    : n_(n), owned_(std::make_unique<Handles>()), opt_(opt) {
  POISE_INVARIANT(n > 0, "CVODE needs at least one state");
  SUNContext ctx = nullptr;
#if SUNDIALS_VERSION_MAJOR >= 7
  check(SUNContext_Create(SUN_COMM_NULL, &ctx), "SUNContext_Create");
#else
  check(SUNContext_Create(nullptr, &ctx), "SUNContext_Create");
#endif
  owned_->context.reset(ctx);
  N_Vector y = N_VNew_Serial(static_cast<sunindextype>(n), ctx);
  owned_->y.reset(y);
  N_Vector tmp = N_VNew_Serial(static_cast<sunindextype>(n), ctx);
  owned_->tmp.reset(tmp);
  require(y && tmp, "CVODE: cannot allocate vectors");
  N_VConst(0.0, y);
  use_weighted_rms_norm(y);              // clones inherit it
  N_VEnableFusedOps_Serial(y, SUNTRUE);  // one loop per linear combination (clones inherit)
  N_VEnableFusedOps_Serial(tmp, SUNTRUE);
  void* mem = CVodeCreate(CV_BDF, ctx);
  require(mem != nullptr, "CVodeCreate failed");
  owned_->memory.reset(mem);
  CVodeSetErrHandlerFn(mem, cvode_error_handler, this);
  check(CVodeInit(mem, cvode_rhs, 0.0, y), "CVodeInit");
  if (opt.atol_per_state.empty()) {
    check(CVodeSStolerances(mem, opt.rtol, opt.atol), "CVodeSStolerances");
  } else {
    POISE_INVARIANT(opt.atol_per_state.size() == n, "CVODE: atol_per_state must have one entry per state");
    std::copy(opt.atol_per_state.begin(), opt.atol_per_state.end(), N_VGetArrayPointer(tmp));
    check(CVodeSVtolerances(mem, opt.rtol, tmp), "CVodeSVtolerances");  // CVODE copies it
  }
  owned_->binding = std::make_unique<CvodeRhsBinding>(CvodeRhsBinding{rhs, user_data});
  check(CVodeSetUserData(mem, owned_->binding.get()), "CVodeSetUserData");
  SUNMatrix a = SUNDenseMatrix(static_cast<sunindextype>(n), static_cast<sunindextype>(n), ctx);
  owned_->matrix.reset(a);
  SUNLinearSolver ls = n <= kSmallDenseMaxSize ? small_dense_linear_solver(n, ctx) : SUNLinSol_Dense(y, a, ctx);
  owned_->solver.reset(ls);
  require(a && ls, "CVODE: cannot create the dense linear solver");
  check(CVodeSetLinearSolver(mem, ls, a), "CVodeSetLinearSolver");
  check(CVodeSetMaxNumSteps(mem, opt.max_steps), "CVodeSetMaxNumSteps");
  if (opt.max_step > 0) check(CVodeSetMaxStep(mem, opt.max_step), "CVodeSetMaxStep");
  if (opt.max_order > 0) check(CVodeSetMaxOrd(mem, opt.max_order), "CVodeSetMaxOrd");
}

CvodeIntegrator::~CvodeIntegrator() = default;  // owned_ frees the handles

void CvodeIntegrator::reset(double t0, std::span<const double> y0) {
  POISE_INVARIANT(y0.size() == n_, "CVODE reset: state of the wrong size");
  N_Vector y = owned_->y.get();
  std::copy(y0.begin(), y0.end(), N_VGetArrayPointer(y));
  check(CVodeReInit(owned_->memory.get(), t0, y), "CVodeReInit", last_error_);
  t_ = t0;
}

double CvodeIntegrator::advance(double t_out, double t_stop, bool one_step) {
  check(CVodeSetStopTime(owned_->memory.get(), t_stop), "CVodeSetStopTime", last_error_);
  sunrealtype t = t_;
  const int flag = CVode(owned_->memory.get(), t_out, owned_->y.get(), &t, one_step ? CV_ONE_STEP : CV_NORMAL);
  check(flag, "CVode", last_error_);
  t_ = t;
  return t_;
}

void CvodeIntegrator::interpolate(double t, std::span<double> y) const {
  POISE_INVARIANT(y.size() == n_, "CVODE interpolate: buffer of the wrong size");
  N_Vector tmp = owned_->tmp.get();
  check(CVodeGetDky(owned_->memory.get(), t, 0, tmp), "CVodeGetDky", last_error_);
  const double* p = N_VGetArrayPointer(tmp);
  std::copy(p, p + n_, y.begin());
}

int CvodeIntegrator::step_polynomial(std::span<double> c, double* tn) const {
  int q = 0;
  CVodeGetLastOrder(owned_->memory.get(), &q);
  CVodeGetCurrentTime(owned_->memory.get(), tn);
  POISE_INVARIANT(c.size() >= (static_cast<std::size_t>(q) + 1) * n_, "CVODE step_polynomial: buffer too small");
  N_Vector tmp = owned_->tmp.get();
  const double* p = N_VGetArrayPointer(tmp);
  double fact = 1.0;
  for (int j = 0; j <= q; ++j) {
    if (j > 1) fact *= j;
    check(CVodeGetDky(owned_->memory.get(), *tn, j, tmp), "CVodeGetDky", last_error_);
    for (std::size_t i = 0; i < n_; ++i) c[static_cast<std::size_t>(j) * n_ + i] = p[i] / fact;
  }
  return q;
}

std::span<const double> CvodeIntegrator::state() const { return {N_VGetArrayPointer(owned_->y.get()), n_}; }

CvodeStats CvodeIntegrator::stats() const {
  long steps = 0, nfe = 0, nfe_ls = 0, nje = 0;
  CVodeGetNumSteps(owned_->memory.get(), &steps);
  CVodeGetNumRhsEvals(owned_->memory.get(), &nfe);
  CVodeGetNumLinRhsEvals(owned_->memory.get(), &nfe_ls);
  CVodeGetNumJacEvals(owned_->memory.get(), &nje);
  return {steps, nfe + nfe_ls, nje};
}

}  // namespace poise::solvers
