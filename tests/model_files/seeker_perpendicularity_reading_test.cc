// The reading of the yaw perpendicularity tolerance, a model key of the seeker_los kind
// ([yaw.perpendicularity] direction, sigma_of, azimuth; issue 21): each reading's draw
// against its definition, the mean square tilt in closed form, the default left as before,
// and the errors of each wrong combination with file, line and key.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/units.h"
#include "engine/study_files/toml_reader.h"
#include "model_files/seeker_model.h"
#include "sampling/design.h"
#include "sampling/distribution.h"
#include "test_util.h"

using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace {

using poise::model_files::load_seeker_model;
using poise::model_files::SeekerModel;
using poise::model_files::SeekerSampler;
using poise::test::TempDir;
namespace ps = poise::sampling;

const std::string kModel = "models/seeker_two_axis_wang2011.toml";
const std::string kReading = "direction = \"random\"\nsigma_of = \"magnitude\"\n";

// The shipped model with its [yaw.perpendicularity] reading replaced by `reading`.
std::string model_with(const TempDir& d, const std::string& reading, const std::string& name = "m.toml") {
  std::string text = poise::test::read_text(poise::test::source_path(kModel));
  text = poise::test::replace_once(text, kReading, reading);
  const std::string path = d.file(name + ".toml");
  poise::test::write_text(path, text);
  return path;
}

struct Loaded {
  SeekerModel model;
  std::string path;
};

// Mean square of the yaw static tilt (rad^2) over a Sobol design, and the first draw's columns.
double mean_square_tilt(const SeekerSampler& s, std::size_t n) {
  const ps::Design d(ps::SamplingMethod::kSobol, 3, n, s.dimension());
  std::vector<double> u(s.dimension()), v(s.dimension());
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    d.point(i, u);
    const auto st = s.draw(u, v);
    sum += st.yaw.static_tilt[0] * st.yaw.static_tilt[0] + st.yaw.static_tilt[1] * st.yaw.static_tilt[1];
  }
  return sum / static_cast<double>(n);
}

class PerpendicularityReading : public ::testing::Test {
 protected:
  SeekerModel load(const std::string& reading) {
    made_.push_back(model_with(dir_, reading, "reading" + std::to_string(made_.size())));
    return load_seeker_model(made_.back());
  }
  std::string error_of(const std::string& reading) {
    try {
      load(reading);
    } catch (const poise::engine::ValidationError& e) {
      return e.what();
    }
    return "";
  }
  TempDir dir_;
  std::vector<std::string> made_;
};

TEST_F(PerpendicularityReading, TheShippedModelStatesTheDefaultReading) {
  const std::string text = poise::test::read_text(poise::test::source_path(kModel));
  ASSERT_NE(text.find(kReading), std::string::npos);
  // Without the keys: the same reading, the same draws.
  const SeekerModel stated = load_seeker_model(poise::test::source_path(kModel));
  const SeekerModel bare = load("");
  EXPECT_TRUE(bare.yaw.tilt_reading.random_direction);
  EXPECT_FALSE(bare.yaw.tilt_reading.per_component);
  const SeekerSampler a(stated), b(bare);
  ASSERT_EQ(a.dimension(), b.dimension());
  EXPECT_EQ(a.columns()[1].name, "yaw_perpendicularity_tilt_arcsec");
  std::vector<double> u(a.dimension(), 0.3), va(a.dimension()), vb(b.dimension());
  u[1] = 0.8;
  u[2] = 0.1;
  const auto sa = a.draw(u, va), sb = b.draw(u, vb);
  EXPECT_EQ(va, vb);
  EXPECT_EQ(sa.yaw.static_tilt, sb.yaw.static_tilt);
  // Magnitude reading: |N(0, sigma)| at u = 0.8 is sigma z(0.9), towards 36 deg.
  const double sigma = 0.004e-3, span = 0.082;
  EXPECT_NEAR(std::hypot(sa.yaw.static_tilt[0], sa.yaw.static_tilt[1]), sigma * ps::standard_normal_quantile(0.9) / span, 1e-15);
  EXPECT_NEAR(std::atan2(sa.yaw.static_tilt[1], sa.yaw.static_tilt[0]), 0.2 * M_PI, 1e-12);
}

TEST_F(PerpendicularityReading, EachReadingDrawsWhatItSays) {
  const double sigma = 0.004e-3, span = 0.082, s2 = sigma * sigma / (span * span);
  const SeekerModel magnitude = load(kReading);
  const SeekerModel component = load("direction = \"random\"\nsigma_of = \"component\"\n");
  const SeekerModel fixed = load("direction = \"fixed\"\nazimuth = \"90 deg\"\n");
  const SeekerSampler sm(magnitude), sc(component), sf(fixed);
  EXPECT_EQ(sc.columns()[1].name, "yaw_perpendicularity_x_arcsec");
  EXPECT_EQ(sc.columns()[2].name, "yaw_perpendicularity_y_arcsec");
  EXPECT_EQ(sf.columns()[1].name, "yaw_perpendicularity_tilt_arcsec");
  // E|tilt|^2: sigma^2 for the magnitude and the fixed readings, 2 sigma^2 per component
  // (within the Sobol design's error, far below the factor 2 between them).
  EXPECT_NEAR(mean_square_tilt(sm, 4096) / s2, 1.0, 0.01);
  EXPECT_NEAR(mean_square_tilt(sc, 4096) / s2, 2.0, 0.02);
  EXPECT_NEAR(mean_square_tilt(sf, 4096) / s2, 1.0, 0.01);
  // Component: x and y from their own coordinates; fixed: signed, along y (90 deg), and the
  // azimuth column records the stated direction.
  std::vector<double> u(sm.dimension(), 0.5), v(sm.dimension());
  u[1] = 0.975;
  u[2] = 0.025;
  const auto c = sc.draw(u, v);
  EXPECT_NEAR(c.yaw.static_tilt[0], sigma * 1.959963984540054 / span, 1e-15);
  EXPECT_NEAR(c.yaw.static_tilt[1], -sigma * 1.959963984540054 / span, 1e-15);
  EXPECT_NEAR(v[1], sigma * 1.959963984540054 / span / poise::units::kRadPerArcsec, 1e-9);
  u[1] = 0.025;
  const auto f = sf.draw(u, v);
  EXPECT_NEAR(f.yaw.static_tilt[0], 0.0, 1e-20);
  EXPECT_NEAR(f.yaw.static_tilt[1], -sigma * 1.959963984540054 / span, 1e-15);
  EXPECT_NEAR(v[2], 90.0, 1e-12);
  EXPECT_NE(fixed.yaw.tilt_reading.describe().find("fixed"), std::string::npos);
}

TEST_F(PerpendicularityReading, WrongCombinationsAreRefusedWithTheirKey) {
  std::string e = error_of("direction = \"diagonal\"\n");
  EXPECT_NE(e.find("yaw.perpendicularity.direction"), std::string::npos) << e;
  EXPECT_NE(e.find("diagonal"), std::string::npos) << e;
  EXPECT_NE(e.find("fixed"), std::string::npos) << e;  // what is accepted
  e = error_of("direction = \"fixed\"\nsigma_of = \"magnitude\"\n");
  EXPECT_NE(e.find("yaw.perpendicularity.sigma_of"), std::string::npos) << e;
  EXPECT_NE(e.find("sigma_of = \"component\" (or no sigma_of) with direction = \"fixed\""), std::string::npos) << e;
  EXPECT_EQ(error_of("direction = \"fixed\"\nsigma_of = \"component\"\n"), "");  // the paper's reading
  e = error_of("direction = \"random\"\nazimuth = \"10 deg\"\n");
  EXPECT_NE(e.find("no azimuth with direction = \"random\""), std::string::npos) << e;
  e = error_of("sigma_of = \"rms\"\n");
  EXPECT_NE(e.find("yaw.perpendicularity.sigma_of"), std::string::npos) << e;
  EXPECT_NE(e.find("magnitude"), std::string::npos) << e;
  // The file and the line of the key are named.
  const std::string text = poise::test::read_text(made_.back());
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(text.find("sigma_of = \"rms\"")), '\n');
  EXPECT_NE(e.find(made_.back() + ":" + std::to_string(line)), std::string::npos) << e;
}

TEST_F(PerpendicularityReading, PitchHasNoDirection) {
  std::string text = poise::test::read_text(poise::test::source_path(kModel));
  text = poise::test::replace_once(text, "Table 1, Eq. 4: Delta_21 = 0.004 mm, read as 1 sigma as the paper does\"\n",
                                   "Table 1, Eq. 4: Delta_21 = 0.004 mm, read as 1 sigma as the paper does\"\n"
                                   "direction = \"fixed\"\n");
  made_.push_back(dir_.file("pitch.toml"));
  poise::test::write_text(made_.back(), text);
  try {
    load_seeker_model(made_.back());
    FAIL() << "accepted a direction on the pitch perpendicularity";
  } catch (const poise::engine::ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("pitch.perpendicularity.direction"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("one direction by definition"), std::string::npos) << e.what();
  }
}

}  // namespace
