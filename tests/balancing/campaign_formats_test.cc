// A balancing campaign's readings as labs keep them (balancing/campaign.h): one campaign written
// in a wide table of amplitude and phase, a long table (a row per sensor's reading, runs by
// name, amplitudes in another unit), real and imaginary parts, phase lead with masses' angles
// counted with rotation, and readings at two speeds. Each gives the same answers as the first
// (or, for the declared senses, the same answers in those senses); wrong input is refused with
// the file, the line and what was expected.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>

#include <fmt/format.h>

#include "balancing/campaign.h"
#include "balancing/campaign_analysis.h"
#include "core/error.h"
#include "engine/study_files/toml_reader.h"
#include "test_util.h"

namespace poise::balancing {
namespace {

using estimators::Phasor;
using test::TempDir;
using test::write_text;

// Two sensors (probe angles 0 and 90 deg), one plane: a = own readings, h = coefficients (mil
// per g, as Poise counts: lag, the probe's angle added). Runs: as found, two trials, an unknown.
const Phasor kA[2] = {std::polar(2.0, 0.5), std::polar(1.5, 2.1)};
const Phasor kH[2] = {std::polar(0.1, 1.0), std::polar(0.08, 2.9)};
const double kProbe[2] = {0.0, 90.0};
const Phasor kMass[4] = {0.0, std::polar(10.0, 0.7), std::polar(8.0, 3.0), std::polar(6.0, -1.2)};

// Sensor s's reading (amplitude mil, phase lag deg as the instrument gives it) on run r.
std::pair<double, double> instrument(int r, int s, double scale = 1.0) {
  const Phasor v = (kA[s] + kH[s] * kMass[r]) * scale;
  double lag = std::arg(v) * 180.0 / M_PI - kProbe[s];
  lag = std::fmod(lag + 720.0, 360.0);
  return {std::abs(v), lag};
}

std::string campaign_toml(const std::string& extra_head, const std::string& sensors, bool with_rotation) {
  std::string runs;
  const char* names[4] = {"as found", "trial 1", "trial 2", "unknown"};
  for (int r = 0; r < 4; ++r) {
    runs += fmt::format("[[run]]\nname = \"{}\"\n", names[r]);
    if (r == 0) runs += "masses = []\n";
    if (r == 1 || r == 2) {
      const double deg = std::arg(kMass[r]) * 180.0 / M_PI * (with_rotation ? -1.0 : 1.0);
      runs += fmt::format("masses = [{{plane = \"p\", mass = \"{} g\", angle = \"{} deg\"}}]\n", std::abs(kMass[r]),
                          deg);
    }
  }
  return "[campaign]\nname = \"formats\"\nreadings = \"r.csv\"\namplitude_unit = \"mil\"\n" + extra_head + "\n" +
         sensors + "[[plane]]\nname = \"p\"\n" + runs;
}

const std::string kWideSensors =
    "[[sensor]]\nname = \"x\"\namplitude = \"x_amp\"\nphase = \"x_deg\"\nangle = \"0 deg\"\n"
    "[[sensor]]\nname = \"y\"\namplitude = \"y_amp\"\nphase = \"y_deg\"\nangle = \"90 deg\"\n";

CampaignAnalyses analyse(TempDir& dir, const std::string& toml, const std::string& csv) {
  write_text(dir.file("c.toml"), toml);
  write_text(dir.file("r.csv"), csv);
  return analyse_campaign(read_balancing_campaign(dir.file("c.toml")));
}

Phasor unknown_mass(const CampaignAnalysis& a) { return a.runs.at(0).unbalance.planes.at(0).value; }

std::string wide_csv(bool lead) {
  std::string csv = "run,x_amp,x_deg,y_amp,y_deg\n";
  for (int r = 0; r < 4; ++r) {
    const auto [ax, px] = instrument(r, 0);
    const auto [ay, py] = instrument(r, 1);
    csv += fmt::format("{},{:.9f},{:.9f},{:.9f},{:.9f}\n", r + 1, ax, lead ? 360.0 - px : px, ay,
                       lead ? 360.0 - py : py);
  }
  return csv;
}

TEST(CampaignFormats, EveryLayoutGivesTheSameAnswers) {
  TempDir dir;
  const auto wide = analyse(dir, campaign_toml("", kWideSensors, false), wide_csv(false));
  ASSERT_EQ(wide.speeds.size(), 1u);
  EXPECT_NEAR(std::abs(unknown_mass(wide.speeds[0]) - kMass[3]), 0.0, 1e-6);

  // Long: runs by name, amplitudes in um (a header's unit), a sensor column.
  std::string long_csv = "# one row per sensor's reading\nRun;Probe;Amp [um];Phase\n";
  const char* names[4] = {"as found", "trial 1", "trial 2", "unknown"};
  for (int r = 0; r < 4; ++r) {
    for (int s = 0; s < 2; ++s) {
      const auto [amp, lag] = instrument(r, s, 25.4);
      long_csv += fmt::format("{};{};{:.9f};{:.9f}\n", names[r], s == 0 ? "x" : "y", amp, lag);
    }
  }
  const std::string long_sensors = "[[sensor]]\nname = \"x\"\nangle = \"0 deg\"\n[[sensor]]\nname = \"y\"\nangle = \"90 deg\"\n";
  const auto longer = analyse(dir,
                              campaign_toml("layout = \"long\"\n[columns]\nrun = \"Run\"\nsensor = \"Probe\"\n"
                                            "amplitude = \"Amp [um]\"\nphase = \"Phase\"",
                                            long_sensors, false),
                              long_csv);
  EXPECT_NEAR(std::abs(unknown_mass(longer.speeds[0]) - kMass[3]), 0.0, 1e-6);
  EXPECT_NEAR(std::abs(longer.speeds[0].calibration.h[1][0].value - kH[1] * std::polar(1.0, 0.0)), 0.0, 1e-7);

  // Real and imaginary parts of the lag phasor (the probe's angle not in them).
  std::string cartesian = "run,x_re,x_im,y_re,y_im\n";
  for (int r = 0; r < 4; ++r) {
    std::string row = std::to_string(r + 1);
    for (int s = 0; s < 2; ++s) {
      const auto [amp, lag] = instrument(r, s);
      row += fmt::format(",{:.9f},{:.9f}", amp * std::cos(lag * M_PI / 180.0), amp * std::sin(lag * M_PI / 180.0));
    }
    cartesian += row + "\n";
  }
  const std::string cartesian_sensors =
      "[[sensor]]\nname = \"x\"\nreal = \"x_re\"\nimaginary = \"x_im\"\n"
      "[[sensor]]\nname = \"y\"\nreal = \"y_re\"\nimaginary = \"y_im\"\nangle = \"90 deg\"\n";
  const auto cart = analyse(dir, campaign_toml("", cartesian_sensors, false), cartesian);
  EXPECT_NEAR(std::abs(unknown_mass(cart.speeds[0]) - kMass[3]), 0.0, 1e-6);
}

// A field report's table: each reading in one cell, "amplitude @ phase", a degree sign or not.
TEST(CampaignFormats, ReadingsWrittenAsAmplitudeAtPhaseInOneCell) {
  TempDir dir;
  std::string csv = "run,X,Y\n";
  for (int r = 0; r < 4; ++r) {
    const auto [ax, px] = instrument(r, 0);
    const auto [ay, py] = instrument(r, 1);
    csv += fmt::format("{},{:.9f} @ {:.9f}\xC2\xB0,{:.9f}/{:.9f}\n", r + 1, ax, px, ay, py);
  }
  const std::string sensors =
      "[[sensor]]\nname = \"x\"\nreading = \"X\"\n[[sensor]]\nname = \"y\"\nreading = \"Y\"\nangle = \"90 deg\"\n";
  const auto a = analyse(dir, campaign_toml("", sensors, false), csv);
  EXPECT_NEAR(std::abs(unknown_mass(a.speeds[0]) - kMass[3]), 0.0, 1e-6);
  try {
    analyse(dir, campaign_toml("", sensors, false), "run,X,Y\n1,2.0 @ 30,2.1 at 40\n");
    FAIL() << "a cell that is no reading was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("r.csv:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("amplitude @ phase"), std::string::npos) << e.what();
  }
}

TEST(CampaignFormats, DeclaredSensesTurnReadingsAndAnswersRound) {
  TempDir dir;
  // The instrument gives lead and the masses' angles count with rotation: the answers come back
  // with rotation, the mirror image of the lag / against-rotation ones.
  const auto a = analyse(dir, campaign_toml("phase = \"lead\"\nweight_angles = \"with_rotation\"", kWideSensors, true),
                         wide_csv(true));
  EXPECT_NEAR(std::abs(unknown_mass(a.speeds[0]) - std::conj(kMass[3])), 0.0, 1e-6);
  const auto lag = analyse(dir, campaign_toml("", kWideSensors, false), wide_csv(false));
  EXPECT_NEAR(std::abs(a.speeds[0].correction_masses.planes[0].value -
                       std::conj(lag.speeds[0].correction_masses.planes[0].value)),
              0.0, 1e-6);
}

TEST(CampaignFormats, ReadingsAtTwoSpeedsAreCalibratedApartBalancingSpeedFirst) {
  TempDir dir;
  std::string csv = "run,speed_rpm,x_amp,x_deg,y_amp,y_deg\n";
  for (const auto& [rpm, scale] : {std::pair{3000.0, 1.0}, std::pair{6005.0, 4.0}}) {
    for (int r = 0; r < 4; ++r) {
      const auto [ax, px] = instrument(r, 0, scale);
      const auto [ay, py] = instrument(r, 1, scale);
      // A speed that jitters by 0.5% is the same speed.
      const double logged = rpm * (r % 2 ? 1.005 : 1.0);
      csv += fmt::format("{},{},{:.9f},{:.9f},{:.9f},{:.9f}\n", r + 1, logged, ax, px, ay, py);
    }
  }
  const auto a = analyse(dir, campaign_toml("balancing_speed = \"3000 rpm\"", kWideSensors, false), csv);
  ASSERT_EQ(a.speeds.size(), 2u);
  EXPECT_NEAR(*a.speeds[0].speed_rpm, 3000.0 * 1.0025, 1e-6);
  EXPECT_NEAR(*a.speeds[1].speed_rpm, 6005.0 * 1.0025, 1e-6);
  EXPECT_NEAR(std::abs(a.speeds[1].calibration.h[0][0].value - 4.0 * kH[0]), 0.0, 1e-7);
  for (const auto& s : a.speeds) EXPECT_NEAR(std::abs(unknown_mass(s) - kMass[3]), 0.0, 1e-6);
}

TEST(CampaignFormats, WrongInputIsRefusedWithFileLineAndWhatWasExpected) {
  TempDir dir;
  const std::string long_sensors = "[[sensor]]\nname = \"x\"\n[[sensor]]\nname = \"y\"\n";
  const std::string head = "layout = \"long\"";
  try {
    analyse(dir, campaign_toml(head, long_sensors, false),
            "run,sensor,amplitude,phase\n1,x,1,10\n1,z,1,10\n");
    FAIL() << "an unknown sensor was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("r.csv:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("one of the campaign's [[sensor]] names: x, y"), std::string::npos) << e.what();
  }
  try {
    analyse(dir, campaign_toml(head, long_sensors, false), "run,sensor,amplitude,phase\n1,x,1,10\n1,x,1,10\n1,y,1,10\n");
    FAIL() << "a run with unequal readings per sensor was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("as many readings of each sensor in run 'as found' (2 of x, 1 of y)"),
              std::string::npos)
        << e.what();
  }
  // Phases in radians read as degrees would give masses ten times too large: refused.
  std::string radians = "Run,x_amp,x_deg,y_amp,y_deg\n";  // "Run": a default header in another case
  for (int r = 0; r < 4; ++r) {
    const auto [ax, px] = instrument(r, 0);
    const auto [ay, py] = instrument(r, 1);
    radians += fmt::format("{},{},{},{},{}\n", r + 1, ax, px * M_PI / 180.0, ay, py * M_PI / 180.0);
  }
  const std::string plain_phase_sensors =
      "[[sensor]]\nname = \"x\"\namplitude = \"x_amp\"\nphase = \"x_ph\"\n"
      "[[sensor]]\nname = \"y\"\namplitude = \"y_amp\"\nphase = \"y_ph\"\n";
  std::string renamed = radians;
  renamed.replace(0, renamed.find('\n'), "Run,x_amp,x_ph,y_amp,y_ph");
  try {
    analyse(dir, campaign_toml("", plain_phase_sensors, false), renamed);
    FAIL() << "phases in radians were read as degrees";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("look like radians"), std::string::npos) << e.what();
  }
  const auto declared = analyse(dir, campaign_toml("phase_unit = \"rad\"", plain_phase_sensors, false), renamed);
  EXPECT_NEAR(std::abs(unknown_mass(declared.speeds[0]) - kMass[3]), 0.0, 1e-6);
  // A [[run]] without readings (a row numbered wrong, a run left out) is named, not dropped.
  try {
    std::string three = wide_csv(false);
    three.erase(three.rfind("4,"));
    analyse(dir, campaign_toml("", kWideSensors, false), three);
    FAIL() << "a run without readings was dropped silently";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("c.toml:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unknown"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("readings of every [[run]]"), std::string::npos) << e.what();
  }
  // A header whose unit is of another kind than the declared amplitudes (um where mil... is a
  // length too: use mm/s) is refused, not read in the declared unit.
  try {
    std::string velocity = wide_csv(false);
    velocity.replace(0, velocity.find('\n'), "run,x_amp [mm/s],x_deg,y_amp,y_deg");
    analyse(dir, campaign_toml("", kWideSensors, false), velocity);
    FAIL() << "a velocity column was read as displacement";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mm/s"), std::string::npos) << e.what();
  }
  try {
    write_text(dir.file("c.toml"), campaign_toml("", kWideSensors, false) + "[[run]]\nname = \"c\"\ncheck = true\n");
    read_balancing_campaign(dir.file("c.toml"));
    FAIL() << "a check run without masses was accepted";
  } catch (const engine::ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("a check run with its masses"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace poise::balancing

namespace poise::balancing {
namespace {

// A correction split onto a plane's holes: the two masses sit on the holes beside its angle, are
// not negative and add up (as vectors) to the correction.
TEST(CorrectionHoles, TheTwoHolesBesideTheAngleAddUpToTheCorrection) {
  for (int holes : {3, 8, 12, 36}) {
    for (double deg = -350.0; deg < 360.0; deg += 17.3) {
      const estimators::Phasor w = std::polar(7.5, deg * M_PI / 180.0);
      const double first = 10.0 * M_PI / 180.0;
      const auto split = split_onto_holes(w, holes, first);
      ASSERT_EQ(split.size(), 2u);
      estimators::Phasor sum = 0.0;
      for (const auto& h : split) {
        EXPECT_GE(h.mass_g, -1e-12);
        const double k = (h.angle - first) / (2.0 * M_PI / holes);
        EXPECT_NEAR(std::remainder(k, 1.0), 0.0, 1e-9) << "a hole's angle";
        sum += std::polar(h.mass_g, h.angle);
      }
      EXPECT_NEAR(std::abs(sum - w), 0.0, 1e-9) << holes << " holes, " << deg << " deg";
    }
  }
}

}  // namespace
}  // namespace poise::balancing
