// Tests of the grouped harmonic sums of the LOS grid (LosGrid::tilts_on_grid, the hot path
// of the seeker study) against the direct form AxisErrorState::tilt: 1e-12 relative to
// the sum of the magnitudes (|s| + sum |A_h|, the scale of the sum's rounding) on the grids
// the shipped studies use, with the shipped model's error draws, and on long grids with
// large and non-integer orders (no drift along the grid). Also: the per-thread phase
// tables are built once per order and reused, and the grid evaluation matches the
// point-by-point chain.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "engine/study_files/study_config.h"
#include "kinds/seeker_los/seeker_los_study.h"
#include "model_files/seeker_model.h"
#include "models/seeker_los_chain.h"
#include "sampling/design.h"
#include "test_util.h"

using namespace poise::kinds::seeker_los;  // the kinds' and model files' own namespaces
using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace {

using poise::models::AxisErrorState;
using poise::models::LosGrid;
using poise::models::PointingError;
using poise::models::SeekerErrorState;
namespace pm = poise::models;

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

double magnitude_scale(const AxisErrorState& a) {
  double s = std::hypot(a.static_tilt[0], a.static_tilt[1]);
  for (int k = 0; k < a.n_harmonics; ++k) s += std::abs(a.harmonics[static_cast<std::size_t>(k)].amplitude);
  return s;
}

// Largest |grouped - direct| / scale over the angles.
double worst_relative(const AxisErrorState& a, const std::vector<double>& phi,
                      std::vector<LosGrid::PhaseTable>& tables) {
  std::vector<Eigen::Vector2d> t(phi.size());
  LosGrid::tilts_on_grid(a, phi, tables, t);
  double worst = 0.0;
  for (std::size_t k = 0; k < phi.size(); ++k) {
    worst = std::max(worst, (t[k] - a.tilt(phi[k])).cwiseAbs().maxCoeff() / magnitude_scale(a));
  }
  return worst;
}

AxisErrorState random_axis(std::mt19937_64& rng, const std::vector<double>& orders) {
  std::uniform_real_distribution<double> amp(1e-7, 5e-5), ph(0.0, 2.0 * kPi);
  AxisErrorState a;
  a.static_tilt = {amp(rng), -amp(rng)};
  for (double n : orders) a.add({(rng() % 2 ? 1.0 : -1.0) * amp(rng), n, ph(rng)});
  return a;
}

// The shipped studies' grids and their model's error draws (the study's own design points).
TEST(SeekerLosHarmonics, GroupedSumsMatchDirectFormOnShippedStudies) {
  const std::string dir = ::poise::test::source_dir();
  for (const char* name : {"los_seeker_wang2011", "los_seeker_wang2011_housing", "los_seeker_wang2011_replicates"}) {
    SCOPED_TRACE(name);
    poise::engine::StudyConfig cfg = poise::engine::load_study(dir + "/studies/" + name + ".toml");
    poise::model_files::SeekerModel model = poise::model_files::load_seeker_model(cfg.model_path, cfg.overrides);
    const std::uint64_t seed = cfg.seed;
    const poise::kinds::seeker_los::SeekerLosStudy study(std::move(cfg), std::move(model), 64, seed);
    const LosGrid& grid = study.grid();
    LosGrid::Workspace ws = grid.make_workspace();
    std::vector<double> u(study.sampler().dimension()), values(u.size());
    const poise::sampling::Design design(study.config().method, seed, 64, u.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < 64; ++i) {
      design.point(i, u);
      const SeekerErrorState s = study.sampler().draw(u, values);
      ASSERT_GT(s.yaw.n_harmonics, 4);
      worst = std::max(worst, worst_relative(s.yaw, grid.alpha(), ws.yaw_phases));
      worst = std::max(worst, worst_relative(s.pitch, grid.beta(), ws.pitch_phases));
    }
    EXPECT_LT(worst, 1e-12);
    // Orders 0 (static, folded into the offset), 1, 2, 3: three tables per axis, built once.
    EXPECT_EQ(ws.yaw_phases.size(), 3u);
    EXPECT_EQ(ws.pitch_phases.size(), 3u);
  }
}

// Long grids, many turns, large and non-integer orders: nothing accumulates along the grid.
TEST(SeekerLosHarmonics, NoDriftOnLongGrids) {
  std::mt19937_64 rng(19);
  const std::vector<double> orders = {1.0, 1.0, 0.0, 2.0, 3.0, 3.0, 0.37, 1.7, 12.0, 24.0, 2.0, 5.5};
  for (const auto& [lo, hi, n] : {std::tuple{-kPi, kPi, std::size_t{100001}},
                                  std::tuple{-30 * kDeg, 30 * kDeg, std::size_t{20001}},
                                  std::tuple{-20.0, 40.0, std::size_t{50000}}}) {
    const std::vector<double> phi = pm::linspace(lo, hi, n);
    std::vector<LosGrid::PhaseTable> tables;
    for (int trial = 0; trial < 3; ++trial) {
      const AxisErrorState a = random_axis(rng, orders);
      EXPECT_LT(worst_relative(a, phi, tables), 1e-12) << "grid [" << lo << ", " << hi << "] x " << n;
      // The far end of the grid, where a recurrence would have drifted most.
      std::vector<Eigen::Vector2d> t(phi.size());
      LosGrid::tilts_on_grid(a, phi, tables, t);
      EXPECT_LT((t.back() - a.tilt(phi.back())).norm(), 1e-12 * magnitude_scale(a));
    }
  }
}

TEST(SeekerLosHarmonics, TablesAreBuiltPerOrderAndReused) {
  const std::vector<double> phi = pm::linspace(-0.5, 0.5, 7);
  std::vector<LosGrid::PhaseTable> tables;
  std::vector<Eigen::Vector2d> t(phi.size());
  AxisErrorState a;
  a.add({1e-5, 1.0, 0.2});
  a.add({2e-5, 1.0, 1.2});  // same order: one group, one table
  a.add({3e-6, 0.0, 0.4});  // static: no table
  LosGrid::tilts_on_grid(a, phi, tables, t);
  ASSERT_EQ(tables.size(), 1u);
  EXPECT_EQ(tables[0].order, 1.0);
  EXPECT_DOUBLE_EQ(tables[0].c[3], 1.0);  // phi = 0
  EXPECT_NEAR(tables[0].s[6], std::sin(0.5), 1e-16);
  AxisErrorState b;
  b.add({1e-5, 2.0, 0.0});
  LosGrid::tilts_on_grid(b, phi, tables, t);
  EXPECT_EQ(tables.size(), 2u);
  LosGrid::tilts_on_grid(a, phi, tables, t);  // known order again: no new table
  EXPECT_EQ(tables.size(), 2u);
  for (std::size_t k = 0; k < phi.size(); ++k) EXPECT_LT((t[k] - a.tilt(phi[k])).norm(), 1e-20);
  // No harmonics: the static tilt everywhere.
  AxisErrorState s;
  s.static_tilt = {1e-5, -2e-5};
  LosGrid::tilts_on_grid(s, phi, tables, t);
  EXPECT_EQ(t[4], Eigen::Vector2d(1e-5, -2e-5));
  std::vector<Eigen::Vector2d> wrong(3);
  EXPECT_THROW(LosGrid::tilts_on_grid(a, phi, tables, wrong), poise::Error);
}

// The whole grid evaluation (grouped sums, precomputed frames) against the chain built point
// by point with the direct sums, on a shipped-size grid and a fine one.
TEST(SeekerLosHarmonics, GridEvaluationMatchesPointwiseChain) {
  std::mt19937_64 rng(7);
  const std::vector<double> orders = {1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 2.0, 2.0, 3.0, 3.0, 2.0, 2.0};
  for (std::size_t n : {std::size_t{13}, std::size_t{181}}) {
    const LosGrid grid(pm::linspace(-30 * kDeg, 30 * kDeg, n), pm::linspace(-30 * kDeg, 30 * kDeg, n));
    LosGrid::Workspace ws = grid.make_workspace();
    std::vector<PointingError> out(grid.size());
    for (int trial = 0; trial < 3; ++trial) {
      SeekerErrorState s{random_axis(rng, orders), random_axis(rng, orders), 2e-5};
      grid.evaluate(s, ws, out);
      for (std::size_t ia = 0; ia < n; ia += n / 13) {
        for (std::size_t ib = 0; ib < n; ib += n / 13) {
          const double a = grid.alpha()[ia], b = grid.beta()[ib];
          const PointingError p = pm::pointing_error(pm::los_direction(s, a, b), a, b);
          const PointingError& g = out[grid.index(ia, ib)];
          // ~1e-4 rad errors from unit vectors: rounding of d - n is ~1e-16 absolute.
          EXPECT_NEAR(g.total, p.total, 1e-15);
          EXPECT_NEAR(g.yaw, p.yaw, 1e-15);
          EXPECT_NEAR(g.pitch, p.pitch, 1e-15);
        }
      }
    }
  }
}

}  // namespace
