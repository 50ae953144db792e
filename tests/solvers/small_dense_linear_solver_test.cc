// The small dense linear solver (Eigen LU behind SUNDIALS' linear solver interface): its
// solves against an independent factorization, its refusal of a singular matrix, and a stiff
// linear ODE integrated through it against the closed-form solution (also past its size
// limit, where SUNLinSol_Dense takes over).
#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <vector>

#include "solvers/cvode_integrator.h"
#include "solvers/small_dense_linear_solver.h"
#include "sundials_context.h"

namespace poise::solvers {
namespace {

using Sundials = test::SundialsContext;

// x from A x = b through the solver (A copied into a SUNDIALS dense matrix).
std::vector<double> solve_through(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, int* setup_flag) {
  Sundials s;
  const auto n = static_cast<sunindextype>(a.rows());
  SUNMatrix m = SUNDenseMatrix(n, n, s.ctx);
  N_Vector x = N_VNew_Serial(n, s.ctx), rhs = N_VNew_Serial(n, s.ctx);
  Eigen::Map<Eigen::MatrixXd>(SUNDenseMatrix_Data(m), n, n) = a;
  Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(rhs), n) = b;
  SUNLinearSolver ls = small_dense_linear_solver(static_cast<std::size_t>(n), s.ctx);
  EXPECT_NE(ls, nullptr);
  EXPECT_EQ(SUNLinSolInitialize(ls), SUNLS_SUCCESS);
  *setup_flag = SUNLinSolSetup(ls, m);
  std::vector<double> out;
  if (*setup_flag == SUNLS_SUCCESS) {
    EXPECT_EQ(SUNLinSolSolve(ls, m, x, rhs, 0.0), SUNLS_SUCCESS);
    out.assign(N_VGetArrayPointer(x), N_VGetArrayPointer(x) + n);
  } else {
    EXPECT_GT(SUNLinSolLastFlag(ls), 0);
  }
  SUNLinSolFree(ls);
  N_VDestroy(x), N_VDestroy(rhs), SUNMatDestroy(m);
  return out;
}

TEST(SmallDenseLinearSolver, SolvesAgreeWithAnIndependentFactorizationAtEverySize) {
  std::mt19937_64 gen(7);
  std::normal_distribution<double> z;
  for (int n = 1; n <= static_cast<int>(kSmallDenseMaxSize); ++n) {
    // CVODE's Newton matrix I - gamma J, with J random and gamma J of order 10.
    Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; ++i) {
      b[i] = z(gen);
      for (int j = 0; j < n; ++j) a(i, j) -= 3.0 * z(gen);
    }
    int flag = -99;
    const std::vector<double> x = solve_through(a, b, &flag);
    ASSERT_EQ(flag, SUNLS_SUCCESS) << "n = " << n;
    const Eigen::VectorXd ref = a.fullPivLu().solve(b);
    const double cond = a.norm() * a.inverse().norm();
    for (int i = 0; i < n; ++i) EXPECT_NEAR(x[static_cast<std::size_t>(i)], ref[i], 1e-13 * cond * ref.norm()) << n;
  }
}

TEST(SmallDenseLinearSolver, ASingularMatrixIsARecoverableSetupFailure) {
  Eigen::MatrixXd a(3, 3);
  a << 1, 2, 3, 2, 4, 6, 0, 1, 1;  // second row twice the first
  int flag = -99;
  EXPECT_TRUE(solve_through(a, Eigen::Vector3d(1, 2, 3), &flag).empty());
  EXPECT_EQ(flag, SUNLS_LUFACT_FAIL);  // > 0: CVODE retries with a smaller step
}

// y' = A y, A symmetric with eigenvalues from -1 to -1e4 (stiff): y(t) = V exp(L t) V^T y0.
struct Linear {
  Eigen::MatrixXd a;
};
int linear_rhs(double, const double* y, double* ydot, void* user) {
  const auto& a = static_cast<const Linear*>(user)->a;
  Eigen::Map<Eigen::VectorXd>(ydot, a.rows()) = a * Eigen::Map<const Eigen::VectorXd>(y, a.rows());
  return 0;
}

void expect_stiff_linear_solution(int n) {
  std::mt19937_64 gen(static_cast<unsigned>(n));
  std::normal_distribution<double> z;
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = z(gen);
  const Eigen::MatrixXd v = m.householderQr().householderQ();
  Eigen::VectorXd lambda(n);
  for (int i = 0; i < n; ++i) lambda[i] = -std::pow(1e4, static_cast<double>(i) / (n - 1));
  Linear lin{v * lambda.asDiagonal() * v.transpose()};
  Eigen::VectorXd y0 = Eigen::VectorXd::Ones(n);
  CvodeOptions opt;
  opt.rtol = 1e-9, opt.atol = 1e-12;
  CvodeIntegrator integ(static_cast<std::size_t>(n), linear_rhs, &lin, opt);
  integ.reset(0.0, std::span<const double>(y0.data(), static_cast<std::size_t>(n)));
  const double t_end = 0.5;
  integ.advance(t_end, t_end, false);
  const Eigen::VectorXd exact = v * (lambda * t_end).array().exp().matrix().asDiagonal() * v.transpose() * y0;
  const auto y = integ.state();
  for (int i = 0; i < n; ++i) EXPECT_NEAR(y[static_cast<std::size_t>(i)], exact[i], 1e-7 * exact.norm()) << n;
  EXPECT_LT(integ.stats().steps, 2000) << "a stiff solve in few steps: the Newton matrix is factorized right";
}

TEST(SmallDenseLinearSolver, StiffLinearSystemMatchesItsClosedFormThroughCvode) {
  for (const int n : {2, 4, 13, 16}) expect_stiff_linear_solution(n);
}

TEST(SmallDenseLinearSolver, LargerSystemsFallBackToSundialsDense) {
  EXPECT_EQ(small_dense_linear_solver(kSmallDenseMaxSize + 1, nullptr), nullptr);
  expect_stiff_linear_solution(static_cast<int>(kSmallDenseMaxSize) + 4);
}

}  // namespace
}  // namespace poise::solvers
