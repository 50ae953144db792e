// calibrate: a fixed, machine-bound workload (libm, dependent floating-point chain, table
// look-ups in L1) of the same character as the engine's inner loops, with no project code:
// the unit that timings are divided by.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <iostream>

#include "nightly_common.h"
#include "nightly_modes.h"

namespace poise::nightly {

double calibration_kernel(std::size_t steps, std::array<double, 4096>& table) {
  double a = 0.3, b = 0.7, acc = 0.0;
  std::uint32_t idx = 1;
  for (std::size_t i = 0; i < steps; ++i) {
    const double s = std::sin(a), c = std::cos(b);
    const double r = std::sqrt(a * a + b * b + 1.0);
    a = 0.5 * a + 0.3 * c + 1e-3 * table[idx];
    b = 0.5 * b + 0.3 * s + 0.1 / r;
    idx = (idx * 1103515245u + 12345u) & 4095u;
    table[idx] += 1e-9 * a;
    acc += a * b;
  }
  return acc;
}

int run_calibrate(const std::vector<std::string>& args) {
  int reps = 5;
  double min_time = 0.2;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--repetitions" && i + 1 < args.size()) {
      reps = static_cast<int>(parse_double(args[++i], "--repetitions"));
    } else if (args[i] == "--min-time" && i + 1 < args.size()) {
      min_time = parse_double(args[++i], "--min-time");
    } else {
      throw InputError("calibrate: unknown argument '" + args[i] + "'");
    }
  }
  if (reps < 1 || min_time <= 0) throw InputError("calibrate: --repetitions >= 1 and --min-time > 0");
  std::array<double, 4096> table{};
  for (std::size_t i = 0; i < table.size(); ++i) table[i] = static_cast<double>(i % 97) / 97.0;
  volatile double sink = 0;
  auto time_steps = [&](std::size_t steps) {
    const std::clock_t t0 = std::clock();  // process CPU time: a busy neighbour does not count
    sink = sink + calibration_kernel(steps, table);
    return static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
  };
  std::size_t steps = 1 << 14;  // grow until one repetition lasts min_time (also warms up)
  for (double t = time_steps(steps); t < min_time; t = time_steps(steps)) {
    const double f = t > 0 ? std::clamp(1.3 * min_time / t, 1.5, 16.0) : 16.0;
    steps = static_cast<std::size_t>(static_cast<double>(steps) * f);
  }
  std::vector<double> values;
  for (int r = 0; r < reps; ++r) values.push_back(time_steps(steps) / static_cast<double>(steps) * 1e9);
  std::cout << json{{"name", "calibration"}, {"unit", "ns"}, {"steps", steps}, {"values", values}}.dump() << '\n';
  return kExitOk;
}

}  // namespace poise::nightly
