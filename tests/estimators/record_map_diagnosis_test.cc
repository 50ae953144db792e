// Tests of estimators/record_map_diagnosis and record_motion: synthetic records of every motion a
// map is read from (a quasi-static map stepped forward and back, with and without time stamps;
// laps one way at jittered time stamps; laps both ways), written here from the physical
// description (torque = M_0 + C sign(velocity) + sum_N T_N sin(N phi + psi_N) + white noise),
// not with Poise's simulator: every planted order found with its amplitude and phase, the
// friction per direction, nothing invented on clean records, estimates never made worse.
#include "estimators/record_map_diagnosis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "estimators/record_motion.h"

namespace poise::estimators {
namespace {

constexpr double kPi = std::numbers::pi;

struct Planted {
  int order;
  double torque, phase;  // N m, rad
};

struct Truth {
  double offset = 0.02, coulomb = 0.015, noise = 0.004;  // N m
  std::vector<Planted> orders{{3, 0.012, 0.4}, {7, 0.05, 2.8}, {12, 0.02, -1.2}, {28, 0.009, 0.3}};
};

double torque_at(const Truth& t, double phi, double direction) {
  double y = t.offset + t.coulomb * direction;
  for (const auto& o : t.orders) y += o.torque * std::sin(o.order * phi + o.phase);
  return y;
}

enum class Motion { kStepsTimed, kStepsNoTime, kLapsForward, kLapsBoth };

// The record of a motion; the torque column holds the torque (no K_T).
OscillationRecord make_record(Motion motion, const Truth& truth, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, truth.noise);
  std::uniform_real_distribution<double> jitter(0.6, 1.4);
  OscillationRecord r;
  r.file = "synthetic";
  double t = 0.0, phi = 0.0;
  auto add = [&](double angle, double direction) {
    r.t.push_back(t);
    r.phi.push_back(angle);
    r.torque.push_back(torque_at(truth, angle, direction) + noise(rng));
  };
  if (motion == Motion::kStepsTimed || motion == Motion::kStepsNoTime) {
    const int points = 256;  // a turn forward, then back
    const double step = 2 * kPi / points;
    for (int sweep = 0; sweep < 2; ++sweep) {
      const double direction = sweep == 0 ? 1.0 : -1.0;
      for (int k = 0; k < points; ++k) {
        const int held = motion == Motion::kStepsNoTime ? 1 : 6;
        for (int h = 0; h < held; ++h) {  // a quick move (2 rows), then held
          const double target = phi + direction * step;
          const double angle = h < 2 && motion == Motion::kStepsTimed ? phi + direction * step * (h + 1) / 2.0 : target;
          add(angle, direction);
          t += 0.01;
        }
        phi += direction * step;
      }
    }
    if (motion == Motion::kStepsNoTime) {
      r.no_time = true;
      for (std::size_t k = 0; k < r.t.size(); ++k) r.t[k] = static_cast<double>(k);
    }
  } else {
    const double speed = 2 * kPi * 0.5;  // 0.5 turn/s
    const double dt = 1e-3;
    for (int sweep = 0; sweep < (motion == Motion::kLapsBoth ? 2 : 1); ++sweep) {
      const double direction = sweep == 0 ? 1.0 : -1.0;
      for (int k = 0; k < 4000; ++k) {  // two turns, jittered stamps
        const double step = dt * jitter(rng);
        t += step;
        phi += direction * speed * step;
        add(phi, direction);
      }
    }
  }
  return r;
}

OscillationOptions options() {
  OscillationOptions o;
  o.kt = 1.0;  // not used: the record holds the torque
  return o;
}

const MapOrder* found(const MapDiagnosis& d, int order) {
  for (const auto& o : d.orders) {
    if (o.order == order) return &o;
  }
  return nullptr;
}

class MapMotion : public ::testing::TestWithParam<Motion> {};

TEST_P(MapMotion, FindsEveryPlantedOrderAndTheFrictionPerDirection) {
  const Truth truth;
  const OscillationRecord rec = make_record(GetParam(), truth, 7);
  const MapDiagnosis d = diagnose_map(rec, options());
  const bool both = GetParam() != Motion::kLapsForward;
  EXPECT_EQ(d.motion.kind, GetParam() == Motion::kLapsForward || GetParam() == Motion::kLapsBoth ? "laps" : "steps");
  EXPECT_EQ(d.motion.timed, GetParam() != Motion::kStepsNoTime);
  for (const auto& p : truth.orders) {
    const MapOrder* o = found(d, p.order);
    ASSERT_NE(o, nullptr) << "order " << p.order << " not found; " << d.orders.size() << " found";
    EXPECT_NEAR(o->amplitude, p.torque, 4 * o->se_amplitude + 0.02 * p.torque) << "order " << p.order;
    EXPECT_NEAR(std::remainder(o->phase - p.phase, 2 * kPi), 0.0, 4 * o->se_phase + 0.02) << "order " << p.order;
  }
  EXPECT_LE(d.orders.size(), truth.orders.size() + 1) << "orders invented";
  EXPECT_EQ(d.coulomb_fitted, both);
  if (both) {
    EXPECT_NEAR(d.coulomb.value, truth.coulomb, 4 * d.coulomb.se);
    EXPECT_NEAR(d.offset.value, truth.offset, 4 * d.offset.se);
  }
  EXPECT_LT(d.rmse_after, 1.3 * truth.noise);
  for (std::size_t k = 1; k < d.steps.size(); ++k) EXPECT_LE(d.steps[k].rmse, d.steps[k - 1].rmse);
  // What this motion cannot show is said, not fitted.
  std::map<std::string, bool> said;
  for (const auto& [what, why] : d.not_identifiable) said[what] = true;
  EXPECT_TRUE(said["inertia"]);
  EXPECT_TRUE(said["damping"]);
  EXPECT_EQ(said["coulomb_friction"], !both);
}

TEST_P(MapMotion, InventsNoOrderOnCleanRecords) {
  Truth clean;
  clean.orders.clear();
  int invented = 0;
  const int runs = 20;
  for (int k = 0; k < runs; ++k) {
    const MapDiagnosis d = diagnose_map(make_record(GetParam(), clean, 100 + static_cast<unsigned>(k)), options());
    invented += d.orders.empty() && d.trends.empty() ? 0 : 1;
  }
  // Family-wise alpha 0.05: about 1 of 20; the binomial 99% bound is 4.
  EXPECT_LE(invented, 4) << invented << " of " << runs;
}

INSTANTIATE_TEST_SUITE_P(EveryMotion, MapMotion,
                         ::testing::Values(Motion::kStepsTimed, Motion::kStepsNoTime, Motion::kLapsForward,
                                           Motion::kLapsBoth),
                         [](const auto& motion) {
                           switch (motion.param) {
                             case Motion::kStepsTimed:
                               return std::string("StepsTimed");
                             case Motion::kStepsNoTime:
                               return std::string("StepsWithoutTime");
                             case Motion::kLapsForward:
                               return std::string("LapsForwardJittered");
                             default:
                               return std::string("LapsBothWays");
                           }
                         });

TEST(RecordMotion, ASwingIsLeftToTheOscillationDiagnosis) {
  OscillationRecord r;
  for (int k = 0; k < 2000; ++k) {
    r.t.push_back(k * 1e-3);
    r.phi.push_back(0.02 * std::sin(2 * kPi * k * 1e-3));
    r.torque.push_back(0.01 * std::cos(2 * kPi * k * 1e-3));
  }
  EXPECT_EQ(record_motion(r, options()).kind, "swing");
  EXPECT_THROW(diagnose_map(r, options()), Error);
}

TEST(RecordMap, ANegativeFrictionIsSaidToBeOutsidePhysics) {
  Truth truth;
  truth.coulomb = -0.015;  // the angle's sign reversed against the current's, say
  const MapDiagnosis d = diagnose_map(make_record(Motion::kLapsBoth, truth, 3), options());
  ASSERT_EQ(d.outside_physics.size(), 1u);
  EXPECT_NE(d.outside_physics[0].find("friction cannot do"), std::string::npos);
}

}  // namespace
}  // namespace poise::estimators
