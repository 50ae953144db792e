#pragma once
/// CVODE's weighted RMS norm, sqrt(sum (x_i w_i)^2 / n), for the serial vectors of Poise's
/// small systems. SUNDIALS 6.4's N_VWrmsNorm_Serial (through N_VWSqrSumLocal_Serial) took 15 %
/// of the gimbal measurement's CPU time at 13 states, called several times a step; this loop
/// (two partial sums) took 3.6 %. The same norm; the sums differ in rounding only.
#include <nvector/nvector_serial.h>

namespace poise::solvers {

sunrealtype weighted_rms_norm(N_Vector x, N_Vector w);

/// Makes `v` (and every clone CVODE makes of it) use weighted_rms_norm.
void use_weighted_rms_norm(N_Vector v);

}  // namespace poise::solvers
