// ISO 21940-21 style tests of the balancing-machine study (balancing_iso_tests.h): the URR
// from the indication of known test masses and the two-plane U_mar test, on a synthetic
// linear machine whose answers are known in closed form; and the rotor-input warnings.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "kinds/balancing_machine/balancing_iso_tests.h"
#include "kinds/balancing_machine/balancing_model.h"
#include "kinds/balancing_machine/balancing_study.h"
#include "engine/study_files/study_config.h"
#include "test_util.h"

using namespace poise::kinds::balancing_machine;  // the kinds' and model files' own namespaces

namespace poise::engine {
namespace {

using cd = std::complex<double>;
constexpr double kPi = 3.14159265358979323846;
constexpr double kZ1 = 0.2, kZ2 = 0.4;

// A linear machine: indicates C u for true plane unbalances u (a gain error g on plane 1 and
// a cross-talk c from plane 2 into plane 1), places masses exactly.
IsoBench linear_machine(double g, cd c) {
  IsoBench b;
  b.indicate = [g, c](const std::vector<models::PlaneMass>& ms) {
    Eigen::Vector2cd u = Eigen::Vector2cd::Zero();
    for (const auto& m : ms) u(m.height == kZ1 ? 0 : 1) += m.mass * m.radius * std::polar(1.0, m.angle);
    return Eigen::Vector2cd((1.0 + g) * u(0) + c * u(1), u(1));
  };
  b.place = [](double m, double r, double a, double z) { return models::PlaneMass{m, r, a, z}; };
  b.plane_1_height = kZ1;
  b.plane_2_height = kZ2;
  return b;
}

TEST(IsoUrr, IndicationOfKnownTestMassesAgainstClosedForm) {
  const std::vector<models::PlaneMass> rotor{{5e-3, 1.0, 0.3, kZ1}, {4e-3, 1.0, 2.0, kZ2}};
  IsoBench perfect = linear_machine(0.0, 0.0);
  const IsoUrr p = iso_urr(perfect, rotor, 0.71, 0.075);
  EXPECT_NEAR(p.plane[0], 1.0, 1e-12);  // the rotor's own residual drops out of the difference
  EXPECT_NEAR(p.plane[1], 1.0, 1e-12);
  // Gain error 2% and cross-talk 0.01 j: plane 1 indicates (1.02 T1 + 0.01 j T2), T2 = j T1:
  // |D - T| / |T| = |0.02 - 0.01| = 0.01.
  IsoBench off = linear_machine(0.02, cd(0.0, 0.01));
  const IsoUrr q = iso_urr(off, rotor, 0.71, 0.075);
  EXPECT_NEAR(q.plane[0], 1.0 - 0.01, 1e-12);
  EXPECT_NEAR(q.plane[1], 1.0, 1e-12);
}

TEST(TwoPlaneUmar, ReadsTheRotorResidualAndTheCrossTalk) {
  // Residual R = 5.4 kg mm in plane 1, test masses 160 g at 75 mm (12 kg mm), 8 positions.
  const double r = 0.075, m = 0.160, res = 5.4e-3;
  const std::vector<models::PlaneMass> rotor{{res, 1.0, 0.0, kZ1}};
  IsoBench perfect = linear_machine(0.0, 0.0);
  const TwoPlaneUmar t = two_plane_umar(perfect, rotor, m, r, 8, 0.0, 6e-3);
  // Independent: readings |R + T e^{i phi_k}| / r.
  double mx = 0, mn = 1e9, mean = 0, dev = 0;
  std::vector<double> vs;
  for (int k = 0; k < 8; ++k) {
    const double v = std::abs(res + m * r * std::polar(1.0, 2 * kPi * k / 8)) / r;
    EXPECT_NEAR(t.readings[0][static_cast<std::size_t>(k)], v, 1e-12);
    mx = std::max(mx, v);
    mn = std::min(mn, v);
    mean += v / 8;
    vs.push_back(v);
  }
  for (double v : vs) dev = std::max(dev, std::abs(v - mean));
  EXPECT_NEAR(t.mean[0], mean, 1e-12);
  EXPECT_NEAR(t.max_deviation[0], dev, 1e-12);
  // The mean of |R + T e^{i phi}| lies above T, so the largest deviation (at the minimum
  // reading) exceeds |R| / r: the band criterion is stricter than (X_max - X_min) / 2.
  EXPECT_GT(dev * r, res);
  EXPECT_NEAR(t.umar[0], (mx - mn) * r / 2, 1e-15);
  EXPECT_NEAR(t.umar[0], res, 1e-12);  // positions 0 and 180 deg hit R's direction exactly
  EXPECT_NEAR(t.umar[1], 0.0, 1e-15);
  EXPECT_EQ(t.pass, dev * r <= 6e-3);
  EXPECT_TRUE(two_plane_umar(perfect, rotor, m, r, 8, 0.0, dev * r * 1.001).pass);
  EXPECT_FALSE(two_plane_umar(perfect, rotor, m, r, 8, 0.0, dev * r * 0.999).pass);
  // Cross-talk 5% from plane 2 into plane 1: with plane 2's mass opposite, plane 1's readings
  // become |R + 0.95 T e^{i phi}| and the mean falls by 5%.
  IsoBench leaky = linear_machine(0.0, 0.05);
  const TwoPlaneUmar u = two_plane_umar(leaky, rotor, m, r, 8, kPi, 6e-3);
  EXPECT_NEAR(u.readings[0][2], std::abs(res + 0.95 * m * r * cd(0, 1)) / r, 1e-12);
}

TEST(BalancingWarnings, DenseRotorAndTestRadiusOutsideTheRotor) {
  test::TempDir d;
  const std::string text = R"([study]
name = "warn"
kind = "balancing_machine"
model = ")" + test::source_path("models/balancing_machine_wang2014.toml") + R"("
[sampling]
method = "sobol"
samples = 2
seed = 1
[procedure]
plane_1_surface = 2
plane_2_surface = 6
estimator = "influence"
calibration_mass = "100 g"
calibration_radius = "50 mm"
[[experiment]]
name = "urr"
type = "urr"
mass = "710 g"
radius = "75 mm"
requirement = 0.9
)";
  test::write_text(d.file("s.toml"), text);
  StudyConfig cfg = load_study(d.file("s.toml"));
  // A rotor of 200 mm diameter: 2,970 kg/m^3 and the 75 mm test radius inside it.
  const BalancingStudy ok(cfg, load_balancing_model(cfg.model_path, {{"rotor.diameter", "200 mm"}}), 2, 1);
  EXPECT_TRUE(ok.warnings().empty());
  // The Wang 2014 rotor as the paper gives it: 47.6 kg in 100 mm x 510 mm is 11,883 kg/m^3,
  // denser than lead, and the paper's test radius of 75 mm lies outside its 50 mm radius.
  const BalancingStudy bad(cfg, load_balancing_model(cfg.model_path, cfg.overrides), 2, 1);
  ASSERT_EQ(bad.warnings().size(), 2u);
  EXPECT_NE(bad.warnings()[0].find("key 'rotor.mass'"), std::string::npos) << bad.warnings()[0];
  EXPECT_NE(bad.warnings()[0].find("above lead's 11340 kg/m^3"), std::string::npos) << bad.warnings()[0];
  EXPECT_NE(bad.warnings()[1].find("key 'experiment[0].radius' = 75 mm lies outside the rotor"), std::string::npos)
      << bad.warnings()[1];
}

}  // namespace
}  // namespace poise::engine
