#pragma once
/// A SUNDIALS linear solver for the small dense systems of Poise's integrators (n <= 16):
/// Eigen's partial-pivoting LU, one fixed-size instance per n (no allocation, loops the
/// compiler unrolls and vectorizes) in place of SUNDIALS' generic dense GETRF/GETRS, which walks
/// column pointers and dominated the gimbal measurement's profile (17 % of its CPU time in
/// GETRS alone for a 13-state system).
///
/// The same factorization as SUNLinSol_Dense (LU with row pivoting of M = I - gamma J, CVODE's
/// Newton matrix); the solves differ only in rounding.
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <cstddef>

namespace poise::solvers {

/// Largest system the solver takes; larger ones use SUNLinSol_Dense.
inline constexpr std::size_t kSmallDenseMaxSize = 16;

/// A new solver for n x n dense SUNMatrix systems (n <= kSmallDenseMaxSize); freed with
/// SUNLinSolFree. nullptr when out of memory.
SUNLinearSolver small_dense_linear_solver(std::size_t n, SUNContext ctx);

}  // namespace poise::solvers
