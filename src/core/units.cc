#include "core/units.h"

#include <charconv>
#include <cmath>
#include <map>
#include <stdexcept>

#include "core/error.h"
#include "core/format.h"

namespace poise::units {
namespace {

// Text quoted in a message: whole up to a line's worth, else its start and its length (a
// 2 MB unit string must not become a 2 MB message).
std::string quoted(std::string_view text) {
  if (text.size() <= 120) return "\"" + std::string(text) + "\"";
  std::size_t cut = 80;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // whole UTF-8 characters
  return "\"" + std::string(text.substr(0, cut)) + "...\" (" + std::to_string(text.size()) + " bytes)";
}

struct UnitDef {
  double factor;
  Dimension dim;
};

const std::map<std::string, UnitDef, std::less<>>& unit_table() {
  static const std::map<std::string, UnitDef, std::less<>> table = {
      // length
      {"m", {1.0, kLength}},
      {"km", {1e3, kLength}},
      {"cm", {1e-2, kLength}},
      {"mm", {1e-3, kLength}},
      {"um", {1e-6, kLength}},
      {"µm", {1e-6, kLength}},
      {"nm", {1e-9, kLength}},
      {"in", {0.0254, kLength}},      // inch, exact by definition
      {"mil", {0.0254e-3, kLength}},  // thousandth of an inch (a "thou")
      {"thou", {0.0254e-3, kLength}},
      {"mils", {0.0254e-3, kLength}},  // as vibration tables write it
      // mass
      {"kg", {1.0, kMass}},
      {"g", {1e-3, kMass}},
      {"mg", {1e-6, kMass}},
      {"lb", {0.45359237, kMass}},      // avoirdupois pound, exact by definition
      {"oz", {0.028349523125, kMass}},  // avoirdupois ounce (1/16 lb)
      // time
      {"s", {1.0, kTime}},
      {"ms", {1e-3, kTime}},
      {"us", {1e-6, kTime}},
      {"ns", {1e-9, kTime}},  // loggers' time stamps (ns since the epoch)
      {"min", {60.0, kTime}},
      {"h", {3600.0, kTime}},
      // current
      {"A", {1.0, kCurrent}},
      {"mA", {1e-3, kCurrent}},
      // angle
      {"rad", {1.0, kAngle}},
      {"mrad", {1e-3, kAngle}},
      {"urad", {1e-6, kAngle}},
      {"µrad", {1e-6, kAngle}},
      {"deg", {kRadPerDeg, kAngle}},
      {"arcmin", {kRadPerDeg / 60.0, kAngle}},
      {"arcsec", {kRadPerArcsec, kAngle}},
      {"rev", {2.0 * kPi, kAngle}},
      // pixel
      // temperature difference (a change or a spread, e.g. "40 K"; no absolute temperatures)
      {"K", {1.0, kTemperature}},
      {"mK", {1e-3, kTemperature}},
      {"px", {1.0, kPixel}},
      {"pixel", {1.0, kPixel}},
      // derived
      {"Hz", {1.0, kFrequency}},
      {"N", {1.0, kForce}},
      {"mN", {1e-3, kForce}},
      {"Nm", {1.0, kTorque}},
      {"mNm", {1e-3, kTorque}},
      {"Pa", {1.0, kPressure}},
      {"kPa", {1e3, kPressure}},
      {"MPa", {1e6, kPressure}},
      {"GPa", {1e9, kPressure}},
      {"gn", {9.80665, kAcceleration}},  // standard acceleration of gravity (ISO 80000-3's g_n)
      {"rpm", {2.0 * kPi / 60.0, Dimension{{0, 0, -1, 0, 1, 0}}}},
      // dimensionless
      {"1", {1.0, kDimensionless}},
      {"%", {1e-2, kDimensionless}},
      {"ppm", {1e-6, kDimensionless}},
  };
  return table;
}

Dimension combine(const Dimension& a, const Dimension& b, int power, std::string_view text) {
  Dimension out = a;
  for (std::size_t i = 0; i < out.e.size(); ++i) {
    const int e = out.e[i] + power * b.e[i];
    // Exponents beyond +-12 are no physical unit (and would wrap around in int8).
    if (e < -12 || e > 12) throw Error("exponent out of range in unit " + quoted(text));
    out.e[i] = static_cast<std::int8_t>(e);
  }
  return out;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Parses a unit expression: factors joined by '*' or '/', each with optional '^int'.
// "r/min" is accepted as a whole word for revolutions per minute.
UnitDef parse_unit(std::string_view text) {
  text = trim(text);
  if (text.empty()) return {1.0, kDimensionless};
  if (text == "r/min") return {2.0 * kPi / 60.0, Dimension{{0, 0, -1, 0, 1, 0}}};
  UnitDef out{1.0, kDimensionless};
  int sign = +1;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t next = text.find_first_of("*/", pos);
    std::string_view factor = trim(text.substr(pos, next == std::string_view::npos ? text.npos : next - pos));
    if (factor.empty()) throw Error("malformed unit " + quoted(text));
    int power = 1;
    if (auto caret = factor.find('^'); caret != std::string_view::npos) {
      std::string_view p = factor.substr(caret + 1);
      auto res = std::from_chars(p.data(), p.data() + p.size(), power);
      if (res.ec != std::errc() || res.ptr != p.data() + p.size() || power < -12 || power > 12) {
        throw Error("malformed exponent in unit " + quoted(text));
      }
      factor = factor.substr(0, caret);
    }
    auto it = unit_table().find(factor);
    if (it == unit_table().end()) {
      throw Error("unknown unit " + quoted(factor));
    }
    out.factor *= std::pow(it->second.factor, sign * power);
    out.dim = combine(out.dim, it->second.dim, sign * power, text);
    if (next == std::string_view::npos) break;
    sign = text[next] == '/' ? -1 : +1;
    pos = next + 1;
  }
  return out;
}

// "m*kg", "m^2*kg*s^-2": the SI units of a dimension, in a form parse_quantity accepts.
std::string si_composition(const Dimension& d) {
  // Positive powers first, then each negative one after a slash ("kg/m^3", "m/s^2"); with no
  // positive power, negative exponents ("s^-1"). Either form parses back.
  static const char* names[] = {"m", "kg", "s", "A", "rad", "px", "K"};
  std::string up, down, all;
  for (std::size_t i = 0; i < d.e.size(); ++i) {
    if (d.e[i] == 0) continue;
    const int power = d.e[i] > 0 ? d.e[i] : -d.e[i];
    std::string factor(names[i]);
    if (power != 1) factor.append("^").append(std::to_string(power));  // (not "^" + s: gcc 12's false -Wrestrict)
    if (d.e[i] > 0) {
      up.append(up.empty() ? "" : "*").append(factor);
    } else {
      down.append("/").append(factor);
    }
    all.append(all.empty() ? "" : "*").append(names[i]);
    if (d.e[i] != 1) all.append("^").append(std::to_string(d.e[i]));
  }
  return up.empty() ? all : up + down;
}

}  // namespace

std::string dimension_name(const Dimension& d) {
  if (d == kDimensionless) return "a dimensionless number";
  if (d == kLength) return "a length";
  if (d == kMass) return "a mass";
  if (d == kTime) return "a time";
  if (d == kCurrent) return "a current";
  if (d == kAngle) return "an angle";
  if (d == kPixel) return "a pixel count";
  if (d == kTemperature) return "a temperature difference";
  if (d == kFrequency) return "a frequency";
  if (d == kForce) return "a force";
  if (d == kTorque) return "a torque";
  if (d == kPressure) return "a pressure";
  if (d == kAcceleration) return "an acceleration";
  if (d == kDensity) return "a density";
  return std::string("a quantity in ").append(si_composition(d));
}

std::string example_unit(const Dimension& d) {
  if (d == kLength) return "mm";
  if (d == kMass) return "kg";
  if (d == kTime) return "s";
  if (d == kCurrent) return "A";
  if (d == kAngle) return "deg";
  if (d == kPixel) return "px";
  if (d == kTemperature) return "K";
  if (d == kFrequency) return "Hz";
  if (d == kForce) return "N";
  if (d == kTorque) return "N*m";
  if (d == kPressure) return "MPa";
  if (d == kAcceleration) return "m/s^2";
  if (d == kDensity) return "kg/m^3";
  if (d == kDimensionless) return "";
  return si_composition(d);  // any other dimension: its SI units, which parse
}

Quantity parse_quantity(std::string_view text) {
  std::string_view s = trim(text);
  if (s.empty()) throw Error("empty value");
  double number = 0.0;
  if (s.size() > 1 && s.front() == '+') s.remove_prefix(1);  // from_chars refuses '+'
  auto res = std::from_chars(s.data(), s.data() + s.size(), number);
  if (res.ec == std::errc::result_out_of_range) {
    throw Error("number out of range (beyond 1e308 or below 1e-308) in " + quoted(text));
  }
  if (res.ec != std::errc()) {
    throw Error("no number at the start of " + quoted(text));
  }
  if (!std::isfinite(number)) throw Error("number is not finite in " + quoted(text));
  std::string_view rest = s.substr(static_cast<std::size_t>(res.ptr - s.data()));
  if (!rest.empty() && rest.front() != ' ' && rest.front() != '\t' && rest.front() != '%') {
    throw Error("expected a space between number and unit in " + quoted(text));
  }
  UnitDef u = parse_unit(rest);
  const double value = number * u.factor;
  if (!std::isfinite(value) || (value == 0.0 && number != 0.0)) {
    throw Error("number out of range once converted to SI units in " + quoted(text));
  }
  return {value, u.dim};
}

double parse_as(std::string_view text, const Dimension& expected) {
  Quantity q;
  const std::string example = example_unit(expected);
  const std::string hint = example.empty() ? std::string("a plain number") : "e.g. \"1 " + example + "\"";
  try {
    q = parse_quantity(text);
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + "; expected " + dimension_name(expected) + ", " + hint);
  }
  if (!(q.dim == expected)) {
    if (q.dim == kDimensionless) {
      throw Error("missing unit; expected " + dimension_name(expected) + ", " + hint);
    }
    throw Error("wrong unit: got " + dimension_name(q.dim) + ", expected " + dimension_name(expected) + ", " + hint);
  }
  return q.value;
}

double unit_factor(std::string_view unit) { return parse_unit(unit).factor; }

std::string format(double value_si, std::string_view unit, int digits) {
  std::string out = significant(value_si / unit_factor(unit), digits);
  if (!unit.empty()) out.append(" ").append(unit);
  return out;
}

}  // namespace poise::units
