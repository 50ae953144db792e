#include "solvers/small_dense_linear_solver.h"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Dense>
#include <new>

namespace poise::solvers {
namespace {

constexpr int kCap = static_cast<int>(kSmallDenseMaxSize);
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kCap, kCap>;
using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kCap, 1>;

struct Content {
  explicit Content(int n) : lu(n) {}
  Eigen::PartialPivLU<SmallMatrix> lu;
  sunindextype last_flag = 0;
};

Content* content(SUNLinearSolver s) { return static_cast<Content*>(s->content); }

SUNLinearSolver_Type get_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID get_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int initialize(SUNLinearSolver s) {
  content(s)->last_flag = 0;
  return SUNLS_SUCCESS;
}

// Factorizes A (column-major, CVODE's Newton matrix). A zero pivot is a recoverable failure:
// CVODE then retries with a smaller step, as with SUNLinSol_Dense.
int setup(SUNLinearSolver s, SUNMatrix a) {
  const auto n = static_cast<Eigen::Index>(SUNDenseMatrix_Rows(a));
  Content* c = content(s);
  c->lu.compute(Eigen::Map<const SmallMatrix>(SUNDenseMatrix_Data(a), n, n));
  const auto& m = c->lu.matrixLU();
  for (Eigen::Index i = 0; i < n; ++i) {
    if (m(i, i) == 0.0) {
      c->last_flag = i + 1;
      return SUNLS_LUFACT_FAIL;
    }
  }
  c->last_flag = 0;
  return SUNLS_SUCCESS;
}

int solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, sunrealtype) {
  Content* c = content(s);
  const Eigen::Index n = c->lu.rows();
  Eigen::Map<SmallVector>(N_VGetArrayPointer(x), n) =
      c->lu.solve(Eigen::Map<const SmallVector>(N_VGetArrayPointer(b), n));
  return SUNLS_SUCCESS;
}

sunindextype last_flag(SUNLinearSolver s) { return content(s)->last_flag; }

int free_solver(SUNLinearSolver s) {
  if (s == nullptr) return SUNLS_SUCCESS;
  delete content(s);
  s->content = nullptr;
  SUNLinSolFreeEmpty(s);
  return SUNLS_SUCCESS;
}

}  // namespace

SUNLinearSolver small_dense_linear_solver(std::size_t n, SUNContext ctx) {
  if (n == 0 || n > kSmallDenseMaxSize) return nullptr;
  SUNLinearSolver s = SUNLinSolNewEmpty(ctx);
  if (s == nullptr) return nullptr;
  s->content = new (std::nothrow) Content(static_cast<int>(n));
  if (s->content == nullptr) {
    SUNLinSolFreeEmpty(s);
    return nullptr;
  }
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
