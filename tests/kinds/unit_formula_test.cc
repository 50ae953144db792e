// Formulas with units (kinds/formula/unit_formula.h): the dimension of each construct, the
// faults refused with where they are, and the text muParser is given.
#include "kinds/formula/unit_formula.h"

#include <gtest/gtest.h>

#include <map>
#include <string>

namespace poise::kinds::formula {
namespace {
using units::Dimension;

const std::map<std::string, Dimension> kNames = {{"shaft", units::kLength},   {"ring", units::kLength},
                                                 {"mass", units::kMass},      {"g", units::kAcceleration},
                                                 {"theta", units::kAngle},    {"k", units::kDimensionless},
                                                 {"s", units::kLength},       {"area", Dimension{{2, 0, 0, 0, 0, 0, 0}}}};

Dimension dim_of(const std::string& text) { return check_formula(text, kNames).dimension; }

// The fault's message and offset, or "" when the formula is accepted.
std::pair<std::string, std::size_t> fault_of(const std::string& text) {
  try {
    check_formula(text, kNames);
  } catch (const FormulaError& e) {
    return {e.what(), e.offset()};
  }
  return {"", 0};
}

TEST(UnitFormula, DimensionsOfEachConstruct) {
  EXPECT_EQ(dim_of("shaft - ring - 2 * 23 mm"), units::kLength);
  EXPECT_EQ(dim_of("mass * g"), units::kForce);
  EXPECT_EQ(dim_of("mass * 9.81 m/s^2 * shaft"), units::kTorque);
  EXPECT_EQ(dim_of("shaft * ring"), (Dimension{{2, 0, 0, 0, 0, 0, 0}}));
  EXPECT_EQ(dim_of("sqrt(area)"), units::kLength);
  EXPECT_EQ(dim_of("area^0.5"), units::kLength);
  EXPECT_EQ(dim_of("pow(shaft, 2)"), dim_of("area"));
  EXPECT_EQ(dim_of("shaft^-1"), (Dimension{{-1, 0, 0, 0, 0, 0, 0}}));
  EXPECT_EQ(dim_of("atan(ring / shaft)"), units::kAngle);
  EXPECT_EQ(dim_of("atan2(ring, shaft)"), units::kAngle);
  EXPECT_EQ(dim_of("sin(theta) + cos(k)"), units::kDimensionless);
  EXPECT_EQ(dim_of("ring / shaft * 1 rad"), units::kAngle);
  EXPECT_EQ(dim_of("max(shaft, ring, 0)"), units::kLength);          // a bare 0 takes any dimension
  EXPECT_EQ(dim_of("shaft > ring ? shaft - ring : 0"), units::kLength);
  EXPECT_EQ(dim_of("2 s"), units::kTime);                          // a constant, though s is a parameter
  EXPECT_EQ(dim_of("2 mm * s"), dim_of("area"));                   // a spaced operator ends the unit
  EXPECT_EQ(dim_of("-shaft^2"), dim_of("area"));                   // -(shaft^2)
  EXPECT_EQ(dim_of("k^k"), units::kDimensionless);                 // a number to a variable power
  EXPECT_EQ(dim_of("pi * shaft^2 / 4"), dim_of("area"));
}

TEST(UnitFormula, MuparserGetsAParenthesisedTextInSi) {
  const CheckedFormula f = check_formula("shaft - 2 * 23 mm + ring * log(k)", kNames);
  EXPECT_EQ(f.muparser_text, "((shaft-(2*(0.023)))+(ring*ln(k)))");
  EXPECT_EQ(f.names, (std::vector<std::string>{"shaft", "ring", "k"}));
  EXPECT_EQ(check_formula("-shaft^2", kNames).muparser_text, "(-(shaft^2))");
  EXPECT_EQ(check_formula("2^3^2", kNames).muparser_text, "(2^(3^2))");  // right-associative
}

TEST(UnitFormula, FaultsSayWhatAndWhere) {
  auto [m, at] = fault_of("shaft - rnig");
  EXPECT_NE(m.find("unknown name 'rnig'"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean 'ring'"), std::string::npos) << m;
  EXPECT_EQ(at, 8u);
  std::tie(m, at) = fault_of("shaft * ring - shaft");
  EXPECT_NE(m.find("'-' joins a quantity in m^2 and a length"), std::string::npos) << m;
  EXPECT_EQ(at, 13u);
  std::tie(m, at) = fault_of("(shaft - ring");
  EXPECT_NE(m.find("expected ')'"), std::string::npos) << m;
  EXPECT_EQ(at, 13u);
  std::tie(m, at) = fault_of("shaft + * ring");
  EXPECT_NE(m.find("unexpected '*'"), std::string::npos) << m;
  EXPECT_EQ(at, 8u);
  EXPECT_NE(fault_of("sin(shaft)").first.find("must be a plain number, not a length"), std::string::npos);
  EXPECT_NE(fault_of("shaft^k").first.find("must be a constant number"), std::string::npos);
  EXPECT_NE(fault_of("shaft^0.5").first.find("fractional power"), std::string::npos);
  EXPECT_NE(fault_of("sqrt(shaft)").first.find("fractional power"), std::string::npos);
  EXPECT_NE(fault_of("sine(theta)").first.find("did you mean 'sin'"), std::string::npos);
  EXPECT_NE(fault_of("sin").first.find("is a function"), std::string::npos);
  EXPECT_NE(fault_of("2 furlongs").first.find("unexpected 'f'"), std::string::npos);
  EXPECT_NE(fault_of("atan2(shaft, theta)").first.find("joins a length"), std::string::npos);
  EXPECT_NE(fault_of("min()").first.find("takes at least 1"), std::string::npos);
  EXPECT_NE(fault_of("").first.find("empty"), std::string::npos);
  EXPECT_TRUE(is_reserved_name("sin"));
  EXPECT_TRUE(is_reserved_name("pi"));
  EXPECT_FALSE(is_reserved_name("shaft"));
}

}  // namespace
}  // namespace poise::kinds::formula
