// The formula kind (src/kinds/formula/): a mechanism written as formulas with units gives the
// same samples as the compiled closed-form kind of the same physics, its faults are refused at
// validation with file, line and column, a formula without a value fails its sample with the
// reason, and the worked example's statistics agree with the closed form of a linear stack.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace poise {
namespace {
using test::read_text;
using test::source_path;
using test::TempDir;

// shaft_sag (src/kinds/shaft_sag/shaft_sag.h) written as formulas: the example model's
// parameters and tolerances, its C++ written out in the same order of operations.
std::string shaft_sag_as_formulas() {
  std::string model = read_text(source_path("models/shaft_sag_example.toml"));
  model = test::replace_once(model, "kind = \"shaft_sag\"", "kind = \"formula\"");
  return model + R"TOML(
[[quantity]]
name = "a"
formula = "load_position"
[[quantity]]
name = "b"
formula = "span - load_position"
[[quantity]]
name = "ei"
formula = "youngs_modulus * pi * (pow(diameter, 4) - pow(bore, 4)) / 64"
[[quantity]]
name = "load"
formula = "load_mass * gravity"
[[quantity]]
name = "slope"
formula = "load * a * b * (b - a) / (3 * ei * span) * 1 rad"
unit = "rad"

[[output]]
name = "tilt_urad"
unit = "urad"
formula = "slope"
[[output]]
name = "los_error_arcsec"
unit = "arcsec"
formula = "abs(los_per_tilt * slope)"
[[output]]
name = "deflection_um"
unit = "um"
formula = "load * a * a * b * b / (3 * ei * span)"
)TOML";
}

std::string study_on(const std::string& kind, const std::string& model_path, std::size_t samples) {
  return "[study]\nname = \"s\"\nkind = \"" + kind + "\"\nmodel = \"" + model_path +
         "\"\n[sampling]\nmethod = \"monte_carlo\"\nsamples = " + std::to_string(samples) + "\nseed = 7\n";
}

TEST(FormulaKind, ShaftSagAsFormulasGivesTheCompiledKindsSamples) {
  TempDir dir;
  test::write_text(dir.file("formula_model.toml"), shaft_sag_as_formulas());
  test::write_text(dir.file("formula.toml"), study_on("formula", dir.file("formula_model.toml"), 2000));
  test::write_text(dir.file("compiled.toml"),
                   study_on("shaft_sag", source_path("models/shaft_sag_example.toml"), 2000));
  for (const char* name : {"formula", "compiled"}) {
    const auto r = test::run_poise(dir, std::string("run '") + dir.file(std::string(name) + ".toml") +
                                            "' --threads 2 --quiet --no-plots --out '" + dir.file(name) + "'");
    ASSERT_EQ(r.status, 0) << name << ": " << r.err;
  }
  const std::string formula = read_text(dir.file("formula") + "/samples.csv");
  EXPECT_EQ(formula.substr(0, formula.find('\n')),
            "sample,status,load_position_mm,diameter_mm,youngs_modulus_GPa,load_mass_g,tilt_urad,los_error_arcsec,"
            "deflection_um,message");
  EXPECT_EQ(formula, read_text(dir.file("compiled") + "/samples.csv"));
}

// Each fault alone, refused by `poise validate` with exit 2, its line and column, and what to do.
TEST(FormulaKind, FaultsAreRefusedWhenTheFileIsRead) {
  TempDir dir;
  const std::string head =
      "[model]\nkind = \"formula\"\nname = \"stack\"\n[parameters]\nshaft = \"208 mm\"\nring = \"1.75 mm\"\n"
      "[[output]]\nname = \"gap\"\nunit = \"mm\"\n";
  struct Case {
    std::string formula, expected;
  };
  const Case cases[] = {
      {"shaft * ring", ":10:11: key 'output[0].formula' = \"shaft * ring\": expected a formula of a length (mm), as "
                       "the unit mm of gap declares: this one gives a quantity in m^2"},
      {"shaft - rnig", "unknown name 'rnig'; did you mean 'ring'?, at column 20"},
      {"shaft - (ring", "expected ')' to close the '(', found the end, at column 25"},
      {"shaft + sin(ring)", "must be a plain number, not a length"},
  };
  for (const Case& c : cases) {
    test::write_text(dir.file("m.toml"), head + "formula = \"" + c.formula + "\"\n");
    test::write_text(dir.file("s.toml"), study_on("formula", dir.file("m.toml"), 10));
    const auto r = test::run_poise(dir, "validate '" + dir.file("s.toml") + "'");
    EXPECT_EQ(r.status, 2) << c.formula;
    EXPECT_NE(r.err.find(dir.file("m.toml") + ":10:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.formula << "\n" << r.err;
  }
  // A parameter that takes a function's name.
  test::write_text(dir.file("m.toml"), test::replace_once(head, "ring = ", "sin = ") + "formula = \"shaft\"\n");
  const auto r = test::run_poise(dir, "validate '" + dir.file("s.toml") + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("parameters.sin"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not a function or constant of the formulas"), std::string::npos) << r.err;
}

// sqrt of a value drawn below zero in about 1% of the samples (mean 2.326 sigma above zero):
// those samples fail with the reason, are counted, and a yield counts them as outside.
TEST(FormulaKind, AFormulaWithoutValueFailsItsSampleAndTheVerdictCountsIt) {
  TempDir dir;
  test::write_text(dir.file("m.toml"),
                   "[model]\nkind = \"formula\"\nname = \"root\"\n[parameters]\nx = \"1 mm^2\"\n"
                   "[tolerances.x]\ntolerance = \"0.43 mm^2\"\ndistribution = \"normal\"\ntolerance_is = \"1sigma\"\n"
                   "[[output]]\nname = \"r\"\nunit = \"mm\"\nformula = \"sqrt(x)\"\n");
  test::write_text(dir.file("s.toml"), study_on("formula", dir.file("m.toml"), 4000) +
                                           "[[requirement]]\noutput = \"r\"\nwithin = [\"0 mm\", \"2 mm\"]\n"
                                           "yield_at_least = 0.95\n");
  const auto r =
      test::run_poise(dir, "run '" + dir.file("s.toml") + "' --quiet --no-plots --out '" + dir.file("run") + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  const auto s = nlohmann::json::parse(read_text(dir.file("run") + "/summary.json"));
  const std::size_t failed = s["failures"]["count"].get<std::size_t>();
  EXPECT_GT(failed, 20u);
  EXPECT_LT(failed, 65u);
  EXPECT_NE(read_text(dir.file("run") + "/samples.csv").find("no value: r = sqrt(x) is not a number"),
            std::string::npos);
  const auto& v = s["requirements"][0];
  EXPECT_EQ(v["failed_samples"].get<std::size_t>(), failed);
  EXPECT_NEAR(v["value"].get<double>(), 1.0 - static_cast<double>(failed) / 4000.0, 1e-12);
}

// The example's gap is linear in its parts: its mean and standard deviation are known in
// closed form (housing N(60, (0.05/3)^2), bearings each N(16 - 0.06, 0.02^2), spacer uniform
// +-0.03: sd 0.03/sqrt(3)), and the run's 95% intervals cover them.
TEST(FormulaKind, WorkedStackUpAgreesWithItsClosedForm) {
  TempDir dir;
  const auto r = test::run_poise(dir, "run '" + source_path("studies/bearing_stack_formula.toml") +
                                          "' --quiet --no-plots --out '" + dir.file("run") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto s = nlohmann::json::parse(read_text(dir.file("run") + "/summary.json"));
  const auto& gap = s["outputs"]["gap"];
  const double mean = 60.0 - 2.0 * 15.94 - 27.6;
  const double sd = std::sqrt(std::pow(0.05 / 3.0, 2) + 2.0 * 0.02 * 0.02 + 0.03 * 0.03 / 3.0);
  // Within 4 standard errors (a bias of that size would fail; chance alone, 1 run in 16,000).
  const double n = gap["n"].get<double>();
  EXPECT_NEAR(gap["mean"]["value"].get<double>(), mean, 4.0 * sd / std::sqrt(n));
  EXPECT_NEAR(gap["std"]["value"].get<double>(), sd, 4.0 * sd / std::sqrt(2.0 * (n - 1.0)));
  EXPECT_EQ(gap["unit"], "mm");
  EXPECT_EQ(s["requirements"][0]["verdict"], "met");
  EXPECT_EQ(s["answer"].get<std::string>().rfind("Every requirement is met (2 of 2)", 0), 0u) << s["answer"];
  EXPECT_NE(read_text(dir.file("run") + "/report.html").find("housing - stack"), std::string::npos);
}

}  // namespace
}  // namespace poise
