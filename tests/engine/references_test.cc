// Declared reference figures ([[reference]]): read strictly, checked against the study's
// outputs, compared with the simulated distribution with the right verdict for each role.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/report/result_sections.h"
#include "engine/results/references.h"
#include "engine/results/result_io.h"
#include "engine/kind_interface/study_kind.h"
#include "sampling/statistics.h"

namespace poise::engine {
namespace {
using nlohmann::json;

ReferenceFigure reference(const std::string& value, const std::string& role, const std::string& statistic = "sample") {
  ReferenceFigure r;
  r.name = "a figure";
  r.output = "torque_mNm";
  r.statistic = statistic;
  r.value_text = value;
  r.value_si = units::parse_quantity(value).value;
  r.source = "test";
  r.role = role;
  r.file = "study.toml";
  r.line = 7;
  return r;
}

struct Fixture {
  std::vector<double> values;
  std::vector<OutputSpec> outputs{{"torque_mNm", "mN*m", ""}};
  json outputs_json;
  Fixture() {
    for (int i = 0; i < 1000; ++i) values.push_back(1.0 + 0.001 * i);  // uniform on [1, 2) mN*m
    outputs_json["torque_mNm"] = summary_json(sampling::summarize(values));
  }
  json compare(const std::vector<ReferenceFigure>& refs) const {
    return compare_references(refs, outputs, outputs_json,
                              [&](const std::string& n) { return n == "torque_mNm" ? &values : nullptr; });
  }
};

TEST(References, OneRealisationIsPlacedInTheSimulatedDistribution) {
  const Fixture f;
  // 1.5 mN*m is the median; 0.5 and 2.5 lie outside; 0.0015 N*m is 1.5 mN*m.
  const json c = f.compare({reference("1.5 mN*m", "validation"), reference("2.5 mN*m", "validation"),
                            reference("0.5 mN*m", "validation"), reference("0.0015 N*m", "validation")});
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0]["verdict"], "agrees");
  EXPECT_NEAR(c[0]["percentile"].get<double>(), 0.501, 1e-9);
  EXPECT_EQ(c[1]["verdict"], "disagrees");
  EXPECT_EQ(c[2]["verdict"], "disagrees");
  EXPECT_NEAR(c[3]["reference"].get<double>(), 1.5, 1e-12);
  EXPECT_EQ(c[3]["verdict"], "agrees");
  // The edges of the central 95%: 1.02 (2.1st percentile) disagrees, 1.03 agrees.
  const json e = f.compare({reference("1.02 mN*m", "validation"), reference("1.03 mN*m", "validation")});
  EXPECT_EQ(e[0]["verdict"], "disagrees");
  EXPECT_EQ(e[1]["verdict"], "agrees");
}

TEST(References, ACalibrationTargetIsNeverCountedAsAgreement) {
  const Fixture f;
  const json c = f.compare({reference("1.5 mN*m", "calibration_target"), reference("9 mN*m", "calibration_target")});
  EXPECT_EQ(c[0]["verdict"], "calibration_target");
  EXPECT_EQ(c[1]["verdict"], "calibration_target");
  const std::string h = references_html(c);
  EXPECT_NE(h.find("not evidence"), std::string::npos);
  EXPECT_EQ(h.find(">agrees<"), std::string::npos);
}

TEST(References, AFigureOfTheDistributionIsComparedWithItsInterval) {
  const Fixture f;
  // The mean of the values is 1.4995 with a 95% half-width of about 0.018.
  const json c = f.compare({reference("1.50 mN*m", "validation", "mean"), reference("1.56 mN*m", "validation", "mean")});
  EXPECT_EQ(c[0]["verdict"], "agrees");
  EXPECT_EQ(c[1]["verdict"], "disagrees");
  ReferenceFigure tol = reference("1.56 mN*m", "validation", "mean");
  tol.tolerance_relative = 0.05;  // within 5%: agrees after all
  EXPECT_EQ(f.compare({tol})[0]["verdict"], "agrees");
}

TEST(References, TooFewSamplesGiveNoVerdict) {
  Fixture f;
  f.values.resize(20);
  f.outputs_json["torque_mNm"] = summary_json(sampling::summarize(f.values));
  const json c = f.compare({reference("1.01 mN*m", "validation")});
  EXPECT_EQ(c[0]["verdict"], "undecided");
  EXPECT_NE(c[0]["why"].get<std::string>().find("20 samples"), std::string::npos);
}

TEST(References, NothingDeclaredGivesNoReportSection) { EXPECT_EQ(references_html(json::array()), ""); }

}  // namespace
}  // namespace poise::engine
