#include "solvers/small_dense_linear_solver.h"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Dense>
#include <memory>
#include <new>
#include <utility>

namespace poise::solvers {
namespace {

// The factorization of one system size. Sizes are compile-time (Eigen's fixed-size LU: the
// triangular solves unrolled; on a dynamic size they took 9 % of the gimbal measurement).
struct Factorization {
  virtual ~Factorization() = default;
  /// LU of the column-major n x n a; 0, or the 1-based index of a zero pivot.
  virtual sunindextype factor(const double* a) = 0;
  virtual void solve(const double* b, double* x) const = 0;
  sunindextype last_flag = 0;
};

template <int N>
struct FixedFactorization final : Factorization {
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;
  Eigen::PartialPivLU<Matrix> lu;
  sunindextype factor(const double* a) override {
    lu.compute(Eigen::Map<const Matrix>(a));
    for (int i = 0; i < N; ++i) {
      if (lu.matrixLU()(i, i) == 0.0) return i + 1;
    }
    return 0;
  }
  void solve(const double* b, double* x) const override {
    Eigen::Map<Vector> out(x);
    out = lu.solve(Eigen::Map<const Vector>(b));
  }
};

// The factorization of size n (1 .. kSmallDenseMaxSize): one factory per compiled size.
template <std::size_t... I>
std::unique_ptr<Factorization> factorization_of(std::size_t n, std::index_sequence<I...>) {
  using Make = std::unique_ptr<Factorization> (*)();
  static constexpr Make kMake[] = {[]() -> std::unique_ptr<Factorization> {
    return std::make_unique<FixedFactorization<static_cast<int>(I) + 1>>();
  }...};
  return kMake[n - 1]();
}

Factorization* content(SUNLinearSolver s) { return static_cast<Factorization*>(s->content); }

SUNLinearSolver_Type get_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID get_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int initialize(SUNLinearSolver s) {
  content(s)->last_flag = 0;
  return SUNLS_SUCCESS;
}

// Factorizes A (column-major, CVODE's Newton matrix). A zero pivot is a recoverable failure:
// CVODE then retries with a smaller step, as with SUNLinSol_Dense.
int setup(SUNLinearSolver s, SUNMatrix a) {
  Factorization* f = content(s);
  f->last_flag = f->factor(SUNDenseMatrix_Data(a));
  return f->last_flag == 0 ? SUNLS_SUCCESS : SUNLS_LUFACT_FAIL;
}

int solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, sunrealtype) {
  content(s)->solve(N_VGetArrayPointer(b), N_VGetArrayPointer(x));
  return SUNLS_SUCCESS;
}

sunindextype last_flag(SUNLinearSolver s) { return content(s)->last_flag; }

int free_solver(SUNLinearSolver s) {
  if (s == nullptr) return SUNLS_SUCCESS;
  std::unique_ptr<Factorization>(content(s)).reset();  // the content small_dense_linear_solver released to it
  s->content = nullptr;
  SUNLinSolFreeEmpty(s);
  return SUNLS_SUCCESS;
}

}  // namespace

SUNLinearSolver small_dense_linear_solver(std::size_t n, SUNContext ctx) {
  if (n == 0 || n > kSmallDenseMaxSize) return nullptr;
  std::unique_ptr<Factorization> f = factorization_of(n, std::make_index_sequence<kSmallDenseMaxSize>{});
  if (!f) return nullptr;
  SUNLinearSolver s = SUNLinSolNewEmpty(ctx);
  if (s == nullptr) return nullptr;
  s->content = f.release();
  s->ops->gettype = get_type;
  s->ops->getid = get_id;
  s->ops->initialize = initialize;
  s->ops->setup = setup;
  s->ops->solve = solve;
  s->ops->lastflag = last_flag;
  s->ops->free = free_solver;
  return s;
}

}  // namespace poise::solvers
