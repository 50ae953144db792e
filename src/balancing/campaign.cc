#include "balancing/campaign.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>

#include "balancing/campaign_design.h"
#include "core/error.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/study_files/toml_reader.h"
#include "estimators/lab_table.h"

namespace poise::balancing {
namespace {
using engine::TomlReader;
using estimators::Phasor;

// Where a sensor's reading is in the readings file (wide layout): amplitude and phase, or real
// and imaginary parts; its mounting angle.
struct SensorColumns {
  std::string first, second;
  bool cartesian = false;
  double angle = 0.0;     // rad
  bool combined = false;  // one column of "amplitude @ phase" cells (first)
};

const units::Dimension kSpeed{{0, 0, -1, 0, 1, 0}};  // rpm's
constexpr double kRadPerSecPerRpm = 2.0 * std::numbers::pi / 60.0;

// One [[run]]: its name and, when known, the masses it carries per plane (g at the plane's radius).
struct DeclaredRun {
  std::string name;
  std::optional<std::vector<Phasor>> masses;
  bool check = false, umar = false;
};

std::optional<std::vector<Phasor>> read_masses(TomlReader& run, const BalancingCampaign& c) {
  if (!run.has("masses")) return std::nullopt;  // a rotor of unknown masses
  std::vector<Phasor> per_plane(c.planes.size(), 0.0);
  for (TomlReader& m : run.table_array("masses")) {
    const std::string plane = m.choice("plane", c.planes);
    const double mass_g = m.quantity("mass", units::kMass, engine::positive) * 1e3;
    // Inside Poise masses' angles count against rotation (campaign.h).
    const double angle = m.quantity("angle", units::kAngle) * (c.weights_with_rotation ? -1.0 : 1.0);
    const double radius = m.quantity("radius", units::kLength, engine::non_negative, 0.0);
    for (std::size_t p = 0; p < c.planes.size(); ++p) {
      if (c.planes[p] != plane) continue;
      // A mass at another radius than the plane's counts by its unbalance m r.
      const double scale = radius > 0.0 && c.plane_radius[p] > 0.0 ? radius / c.plane_radius[p] : 1.0;
      per_plane[p] += std::polar(mass_g * scale, angle);
    }
  }
  return per_plane;
}

DeclaredRun read_run(TomlReader& r, const BalancingCampaign& c) {
  DeclaredRun d{r.string("name"), read_masses(r, c), r.boolean("check", false), r.boolean("umar", false)};
  if (d.umar && !d.check) {
    r.error("umar", "true", "a check run (check = true): a run of the U_mar test is left out of the calibration");
  }
  if (d.check && !d.masses) {
    r.error("check", "true",
            "a check run with its masses: `masses = [...]` (the masses added, known, that the calibration leaves "
            "out and the answer is compared with)");
  }
  return d;
}

}  // namespace

namespace {

// What the campaign file says of the readings file, beside the sensors.
struct ReadingsLayout {
  std::string file;
  bool long_layout = false, lead = false, weights_with_rotation = false, phase_unit_declared = false;
  units::Dimension amplitude_dim;
  double amplitude_factor = 1.0;  // SI per amplitude unit
  std::string phase_unit = "deg";
  std::vector<SensorColumns> sensors;
  estimators::ColumnMapping columns;  // role -> header
};

SensorColumns read_sensor_columns(TomlReader& s) {
  SensorColumns out;
  out.angle = s.quantity("angle", units::kAngle, {}, 0.0);
  if (s.has("reading")) {  // a field report's "2.07 @ 335" cells
    out.combined = true;
    out.first = s.string("reading");
    return out;
  }
  out.cartesian = s.has("real") || s.has("imaginary");
  out.first = s.string(out.cartesian ? "real" : "amplitude");
  out.second = s.string(out.cartesian ? "imaginary" : "phase");
  return out;
}

std::vector<estimators::ColumnRole> column_roles(const BalancingCampaign& c, const ReadingsLayout& l) {
  using estimators::ColumnRole;
  std::vector<ColumnRole> roles = {{"run", {"run"}, units::kDimensionless, "1", true, "run (its number or name)", true},
                                   {"speed", {"speed", "speed_rpm", "rpm"}, kSpeed, "rpm", false, "speed", false}};
  const auto reading_roles = [&](const std::string& prefix, const SensorColumns& sc, const std::string& who) {
    if (sc.combined) {
      roles.push_back({prefix + "reading",
                       {sc.first},
                       units::kDimensionless,
                       "1",
                       true,
                       who + "reading (amplitude @ phase)",
                       true});
    } else if (sc.cartesian) {
      roles.push_back({prefix + "real", {sc.first}, l.amplitude_dim, c.amplitude_unit, true, who + "real part"});
      roles.push_back(
          {prefix + "imaginary", {sc.second}, l.amplitude_dim, c.amplitude_unit, true, who + "imaginary part"});
    } else {
      roles.push_back({prefix + "amplitude", {sc.first}, l.amplitude_dim, c.amplitude_unit, true, who + "amplitude"});
      roles.push_back({prefix + "phase", {sc.second}, units::kAngle, l.phase_unit, true, who + "phase"});
    }
  };
  if (l.long_layout) {
    roles.push_back({"sensor", {"sensor"}, units::kDimensionless, "1", true, "sensor's name", true});
    const bool cartesian = l.columns.header.count("real") || l.columns.header.count("imaginary");
    reading_roles("", {cartesian ? "real" : "amplitude", cartesian ? "imaginary" : "phase", cartesian, 0.0}, "");
  } else {
    for (std::size_t s = 0; s < c.sensors.size(); ++s) {
      reading_roles(c.sensors[s] + ".", l.sensors[s], c.sensors[s] + "'s ");
    }
  }
  for (auto& r : roles) r.unit_by_default = true;  // the campaign declares the units
  return roles;
}

// One row's reading of one sensor as Poise counts it (lag, the probe's angle added), in the
// campaign's amplitude unit.
// A cell holding a reading as field reports print it: "2.07 @ 335", "2.07@335°", "2.07/335 deg",
// "2.07 ∠ 335": the amplitude in the campaign's amplitude unit, the phase in degrees.
Phasor polar_cell(const std::string& cell, const std::string& file, std::size_t line, const std::string& what) {
  std::string text = cell;
  for (const std::string mark : {"\xC2\xB0", "deg"}) {  // a degree sign or "deg" after the phase
    if (const auto at = text.find(mark); at != std::string::npos) text.erase(at, mark.size());
  }
  std::size_t split = std::string::npos, width = 1;
  for (const std::string sep : {"@", "\xE2\x88\xA0", "/"}) {  // @, the angle sign, a slash
    if (const auto at = text.find(sep); at != std::string::npos && split == std::string::npos) {
      split = at;
      width = sep.size();
    }
  }
  char* end = nullptr;
  double amplitude = 0.0, phase = 0.0;
  bool ok = split != std::string::npos;
  if (ok) {
    const std::string a = text.substr(0, split), p = text.substr(split + width);
    amplitude = std::strtod(a.c_str(), &end);
    ok = end != a.c_str() &&
         std::all_of(static_cast<const char*>(end), a.c_str() + a.size(), [](char ch) { return ch == ' '; });
    phase = std::strtod(p.c_str(), &end);
    ok = ok && end != p.c_str() &&
         std::all_of(static_cast<const char*>(end), p.c_str() + p.size(), [](char ch) { return ch == ' '; }) &&
         std::isfinite(amplitude) && std::isfinite(phase) && amplitude >= 0.0;
  }
  if (!ok) {
    throw InputError(
        SourceLocation{file, static_cast<int>(line), 0}, what, cell.empty() ? "(empty)" : cell,
        "a reading as amplitude @ phase in degrees, e.g. \"2.07 @ 335\" (also 2.07@335\xC2\xB0, 2.07/335)");
  }
  return std::polar(amplitude, phase * units::kRadPerDeg);
}

Phasor reading_at(const estimators::LabTable& t, const std::string& prefix, std::size_t row, const ReadingsLayout& l,
                  const SensorColumns& sc) {
  Phasor z;
  if (sc.combined) {
    std::string cell = t.text.at(prefix + "reading")[row];
    if (t.delimiter == "semicolon" || t.delimiter == "tab") std::replace(cell.begin(), cell.end(), ',', '.');
    z = polar_cell(cell, t.file, t.lines[row], "column " + sc.first) * l.amplitude_factor;  // in the amplitude unit
    if (l.phase_unit == "rad") z = std::polar(std::abs(z), std::arg(z) / units::kRadPerDeg);
  } else {
    z = sc.cartesian ? Phasor(t.at(prefix + "real")[row], t.at(prefix + "imaginary")[row])
                     : std::polar(t.at(prefix + "amplitude")[row], t.at(prefix + "phase")[row]);
  }
  z /= l.amplitude_factor;
  if (l.lead) z = std::conj(z);
  return z * std::polar(1.0, sc.angle);
}

std::size_t run_of(const std::string& cell, const std::vector<DeclaredRun>& declared, const std::string& file,
                   std::size_t line, const std::string& campaign) {
  for (std::size_t k = 0; k < declared.size(); ++k) {
    if (declared[k].name == cell) return k;
  }
  char* end = nullptr;
  const double number = std::strtod(cell.c_str(), &end);
  if (end != cell.c_str() && *end == '\0' && number >= 1.0 && number <= static_cast<double>(declared.size()) &&
      number == std::round(number)) {
    return static_cast<std::size_t>(number) - 1;
  }
  throw InputError(SourceLocation{file, static_cast<int>(line), 0}, "run", cell,
                   "a run's number, 1 to " + std::to_string(declared.size()) + " (the [[run]] tables of " + campaign +
                       ", in order), or a run's name");
}

}  // namespace

namespace {

// The speed groups: speeds within 2% of a group's lowest are one; each group's mean.
std::vector<double> speed_groups(std::vector<double> speeds) {
  std::sort(speeds.begin(), speeds.end());
  std::vector<double> means;
  std::size_t first = 0;
  for (std::size_t k = 1; k <= speeds.size(); ++k) {
    if (k == speeds.size() || speeds[k] > 1.02 * speeds[first]) {
      double sum = 0.0;
      for (std::size_t j = first; j < k; ++j) sum += speeds[j];
      means.push_back(sum / static_cast<double>(k - first));
      first = k;
    }
  }
  return means;
}

std::optional<double> group_of(const std::vector<double>& groups, double rpm) {
  for (double g : groups) {
    if (std::abs(rpm - g) <= 0.02 * g) return g;
  }
  return std::nullopt;
}

// The rows of a long table assembled into readings of every sensor: the k-th row of a sensor in
// a run (at a speed) is the k-th reading of that run.
void assemble_long(const estimators::LabTable& t, const std::vector<std::size_t>& run_index,
                   const std::vector<std::optional<double>>& speed, const std::vector<DeclaredRun>& declared,
                   const ReadingsLayout& l, BalancingCampaign& c) {
  struct Key {
    std::size_t run;
    double speed;
    auto operator<=>(const Key&) const = default;
  };
  std::map<Key, std::vector<std::vector<std::pair<Phasor, std::size_t>>>> by_sensor;
  for (std::size_t row = 0; row < t.size(); ++row) {
    const std::string& name = t.text.at("sensor")[row];
    const auto it = std::find(c.sensors.begin(), c.sensors.end(), name);
    if (it == c.sensors.end()) {
      std::string names;
      for (const auto& n : c.sensors) names += (names.empty() ? "" : ", ") + n;
      throw InputError(SourceLocation{t.file, static_cast<int>(t.lines[row]), 0}, "sensor", name,
                       "one of the campaign's [[sensor]] names: " + names);
    }
    const auto s = static_cast<std::size_t>(it - c.sensors.begin());
    auto& cells = by_sensor[{run_index[row], speed[row].value_or(0.0)}];
    cells.resize(c.sensors.size());
    cells[s].push_back({reading_at(t, "", row, l, l.sensors.empty() ? SensorColumns{} : l.sensors[s]), t.lines[row]});
  }
  for (const auto& [key, cells] : by_sensor) {
    for (std::size_t s = 0; s < c.sensors.size(); ++s) {
      if (cells[s].size() == cells[0].size()) continue;
      const std::size_t line = cells[s].empty() ? cells[0].front().second : cells[s].front().second;
      throw InputError(SourceLocation{t.file, static_cast<int>(line), 0}, "sensor", c.sensors[s],
                       "as many readings of each sensor in run '" + declared[key.run].name + "' (" +
                           std::to_string(cells[0].size()) + " of " + c.sensors[0] + ", " +
                           std::to_string(cells[s].size()) + " of " + c.sensors[s] + ")");
    }
    for (std::size_t k = 0; k < cells[0].size(); ++k) {
      const DeclaredRun& d = declared[key.run];
      estimators::BalancingRun run{d.name, {}, d.masses, d.check, key.run, std::nullopt};
      if (key.speed > 0.0) run.speed_rpm = key.speed;
      for (std::size_t s = 0; s < c.sensors.size(); ++s) run.readings.push_back(cells[s][k].first);
      c.runs.push_back(std::move(run));
    }
  }
}

ReadingsLayout read_layout(TomlReader& root, TomlReader& head, BalancingCampaign& c, const std::string& path) {
  ReadingsLayout l;
  l.file = (std::filesystem::path(path).parent_path() / head.string("readings")).string();
  c.amplitude_unit = head.string("amplitude_unit");
  try {
    const auto q = engine::unit_quantity(c.amplitude_unit);
    l.amplitude_dim = q.dim;
    l.amplitude_factor = q.value;
  } catch (const Error& e) {
    head.error("amplitude_unit", engine::quote_value(c.amplitude_unit),
               std::string("the amplitudes' unit, e.g. \"um\", \"mil\", \"mm/s\" or \"gn\" (") + e.what() + ")");
  }
  l.lead = head.choice("phase", {"lag", "lead"}, "lag") == "lead";
  c.phase_lead = l.lead;
  l.phase_unit_declared = head.has("phase_unit");
  l.phase_unit = head.choice("phase_unit", {"deg", "rad"}, "deg");
  l.weights_with_rotation =
      head.choice("weight_angles", {"against_rotation", "with_rotation"}, "against_rotation") == "with_rotation";
  c.weights_with_rotation = l.weights_with_rotation;
  l.long_layout = head.choice("layout", {"wide", "long"}, "wide") == "long";
  if (head.has("reading_noise")) {
    c.reading_noise = head.quantity("reading_noise", l.amplitude_dim, engine::positive) / l.amplitude_factor;
  }
  if (head.has("balancing_speed")) {
    c.balancing_speed_rpm = head.quantity("balancing_speed", kSpeed, engine::positive) / kRadPerSecPerRpm;
  }
  if (root.has("columns")) {
    TomlReader cols = root.table("columns");
    const std::vector<std::string> keys =
        l.long_layout ? std::vector<std::string>{"run", "speed", "sensor", "amplitude", "phase", "real", "imaginary"}
                      : std::vector<std::string>{"run", "speed"};
    for (const auto& k : keys) {
      if (cols.has(k)) l.columns.header[k] = cols.string(k);
    }
  }
  for (TomlReader& s : root.table_array("sensor")) {
    c.sensors.push_back(s.string("name"));
    if (l.long_layout) {
      l.sensors.push_back({"", "", false, s.quantity("angle", units::kAngle, {}, 0.0)});
    } else {
      l.sensors.push_back(read_sensor_columns(s));
    }
  }
  return l;
}

// Phases that all lie within 2 pi "degrees" are radians read as degrees: refused unless the
// header or the campaign says degrees (a phase column of four or more readings in degrees spans
// more than 6.3 deg).
void refuse_phases_in_radians(const estimators::LabTable& t, const ReadingsLayout& l, const BalancingCampaign& c) {
  if (l.phase_unit_declared || t.size() < 4) return;
  for (const auto& [role, header] : t.header) {
    if (role.size() < 5 || role.compare(role.size() - 5, 5, "phase") != 0) continue;
    if (header.find("deg") != std::string::npos || header.find("\xC2\xB0") != std::string::npos) continue;
    const auto& v = t.at(role);
    // 2 pi read as degrees, in rad
    const double radian_in_degrees = 2.0 * std::numbers::pi * units::kRadPerDeg;
    const bool small = std::all_of(v.begin(), v.end(), [&](double x) { return std::abs(x) <= radian_in_degrees; });
    if (!small) continue;
    throw InputError(
        SourceLocation{t.file, static_cast<int>(t.header_line), 0}, "column " + header, "every phase within +-6.3",
        "phases in degrees: these look like radians; give the unit in the header (\"" + header +
            " [rad]\") or the campaign's phase_unit = \"rad\" (or \"deg\", to keep degrees) for " + c.name);
  }
}

// Every declared run must have readings: a run left out of the file (or a row numbered wrong)
// would change the answer silently.
void refuse_runs_without_readings(const BalancingCampaign& c, const std::vector<DeclaredRun>& declared,
                                  const std::vector<int>& lines, const std::string& readings) {
  std::vector<bool> seen(declared.size(), false);
  for (const auto& r : c.runs) seen[r.declared] = true;
  for (std::size_t k = 0; k < declared.size(); ++k) {
    if (seen[k]) continue;
    throw InputError(SourceLocation{c.file, k < lines.size() ? lines[k] : 0, 0}, "run[" + std::to_string(k) + "]",
                     declared[k].name,
                     "readings of every [[run]] in " + readings + " (run " + std::to_string(k + 1) +
                         " or its name; none found): add its rows, or remove the [[run]]");
  }
}

}  // namespace

BalancingCampaign read_balancing_campaign(const std::string& path) {
  const toml::table doc = engine::parse_toml_file(path);
  auto ctx = std::make_shared<engine::ReadContext>();
  ctx->file = path;
  TomlReader root(doc, ctx);
  BalancingCampaign c;
  c.file = path;
  TomlReader head = root.table("campaign");
  c.name = head.string("name");
  const ReadingsLayout l = read_layout(root, head, c, path);
  for (const auto& sc : l.sensors) c.sensor_angle.push_back(sc.angle);
  for (TomlReader& p : root.table_array("plane")) {
    c.planes.push_back(p.string("name"));
    c.plane_radius.push_back(p.quantity("radius", units::kLength, engine::non_negative, 0.0));
    const std::int64_t holes = p.integer("holes", 0, 3600, 0);
    if (holes == 1 || holes == 2)
      p.error("holes", std::to_string(holes),
              "3 or more equally spaced holes (two opposite holes reach one line only), or none");
    c.plane_holes.push_back(static_cast<int>(holes));
    c.plane_first_hole.push_back(p.quantity("first_hole", units::kAngle, {}, 0.0));
  }
  std::vector<DeclaredRun> declared;
  std::vector<int> run_lines;
  for (TomlReader& r : root.table_array("run")) {
    declared.push_back(read_run(r, c));
    run_lines.push_back(r.line_of("name"));
  }
  if (root.has("design")) {
    TomlReader d = root.table("design");
    c.design = read_design_link(d, c, path);
  }
  if (c.sensors.empty()) root.error("sensor", "", "at least one [[sensor]] with name, amplitude and phase");
  if (c.planes.empty()) root.error("plane", "", "at least one [[plane]] with a name");
  if (declared.empty()) root.error("run", "", "at least one [[run]] with a name and its masses");
  engine::finish(doc, *ctx);
  c.declared_runs = declared.size();
  for (const auto& d : declared) c.umar_run.push_back(d.umar);

  estimators::ColumnMapping mapping = l.columns;
  mapping.naming =
      "the campaign's [columns] table (run, speed; sensor, amplitude, phase in a long layout) or its "
      "[[sensor]] keys (amplitude and phase, real and imaginary, or reading): " +
      path;
  const estimators::LabTable t = estimators::read_lab_table(l.file, column_roles(c, l), mapping);
  refuse_phases_in_radians(t, l, c);
  std::vector<std::size_t> run_index;
  std::vector<double> speeds;
  for (std::size_t row = 0; row < t.size(); ++row) {
    run_index.push_back(run_of(t.text.at("run")[row], declared, l.file, t.lines[row], path));
    if (t.has("speed")) speeds.push_back(t.at("speed")[row] / kRadPerSecPerRpm);
  }
  c.speeds_rpm = speed_groups(speeds);
  std::vector<std::optional<double>> speed(t.size());
  for (std::size_t row = 0; row < speeds.size(); ++row) speed[row] = group_of(c.speeds_rpm, speeds[row]);
  if (l.long_layout) {
    assemble_long(t, run_index, speed, declared, l, c);
  } else {
    for (std::size_t row = 0; row < t.size(); ++row) {
      const DeclaredRun& d = declared[run_index[row]];
      estimators::BalancingRun run{d.name, {}, d.masses, d.check, run_index[row], speed[row]};
      for (std::size_t s = 0; s < c.sensors.size(); ++s) {
        run.readings.push_back(reading_at(t, c.sensors[s] + ".", row, l, l.sensors[s]));
      }
      c.runs.push_back(std::move(run));
    }
  }
  refuse_runs_without_readings(c, declared, run_lines, l.file);
  return c;
}

}  // namespace poise::balancing
