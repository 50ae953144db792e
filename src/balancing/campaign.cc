#include "balancing/campaign.h"

#include <cmath>
#include <filesystem>
#include <optional>

#include "core/error.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/study_files/toml_reader.h"
#include "estimators/lab_table.h"

namespace poise::balancing {
namespace {
using engine::TomlReader;
using estimators::Phasor;

struct SensorColumns {
  std::string amplitude, phase;
  double angle = 0.0;  // rad
};

// One [[run]]: its name and, when known, the masses it carries per plane (g at the plane's radius).
struct DeclaredRun {
  std::string name;
  std::optional<std::vector<Phasor>> masses;
  bool check = false;
};

std::optional<std::vector<Phasor>> read_masses(TomlReader& run, const BalancingCampaign& c) {
  if (!run.has("masses")) return std::nullopt;  // a rotor of unknown masses
  std::vector<Phasor> per_plane(c.planes.size(), 0.0);
  for (TomlReader& m : run.table_array("masses")) {
    const std::string plane = m.choice("plane", c.planes);
    const double mass_g = m.quantity("mass", units::kMass, engine::positive) * 1e3;
    const double angle = m.quantity("angle", units::kAngle);
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
  DeclaredRun d{r.string("name"), read_masses(r, c), r.boolean("check", false)};
  if (d.check && !d.masses) {
    r.error("check", "true",
            "a check run with its masses: `masses = [...]` (the masses added, known, that the calibration leaves "
            "out and the answer is compared with)");
  }
  return d;
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
  const std::string readings = head.string("readings");
  c.amplitude_unit = head.string("amplitude_unit");
  units::Dimension amplitude_dim;
  try {
    amplitude_dim = engine::unit_quantity(c.amplitude_unit).dim;
  } catch (const Error& e) {
    head.error("amplitude_unit", engine::quote_value(c.amplitude_unit),
               std::string("the amplitudes' unit, e.g. \"um\", \"mil\" or \"mm/s\" (") + e.what() + ")");
  }
  const bool lead = head.choice("phase", {"lag", "lead"}, "lag") == "lead";
  std::vector<SensorColumns> columns;
  for (TomlReader& s : root.table_array("sensor")) {
    c.sensors.push_back(s.string("name"));
    columns.push_back({s.string("amplitude"), s.string("phase"), s.quantity("angle", units::kAngle, {}, 0.0)});
  }
  for (TomlReader& p : root.table_array("plane")) {
    c.planes.push_back(p.string("name"));
    c.plane_radius.push_back(p.quantity("radius", units::kLength, engine::non_negative, 0.0));
  }
  std::vector<DeclaredRun> declared;
  for (TomlReader& r : root.table_array("run")) declared.push_back(read_run(r, c));
  if (c.sensors.empty()) root.error("sensor", "", "at least one [[sensor]] with name, amplitude and phase");
  if (c.planes.empty()) root.error("plane", "", "at least one [[plane]] with a name");
  engine::finish(doc, *ctx);
  c.declared_runs = declared.size();

  std::vector<estimators::ColumnRole> roles = {{"run", {"run"}, units::kDimensionless, "1", true, "run number"}};
  for (std::size_t s = 0; s < c.sensors.size(); ++s) {
    roles.push_back({c.sensors[s] + ".amplitude",
                     {columns[s].amplitude},
                     amplitude_dim,
                     c.amplitude_unit,
                     true,
                     c.sensors[s] + "'s amplitude"});
    roles.push_back(
        {c.sensors[s] + ".phase", {columns[s].phase}, units::kAngle, "deg", true, c.sensors[s] + "'s phase"});
  }
  const std::filesystem::path table_path = std::filesystem::path(path).parent_path() / readings;
  const estimators::LabTable t = estimators::read_lab_table(table_path.string(), roles, {});
  const double amplitude_factor = engine::unit_quantity(c.amplitude_unit).value;
  for (std::size_t row = 0; row < t.size(); ++row) {
    const double number = t.at("run")[row];
    if (!(number >= 1.0 && number <= static_cast<double>(declared.size()) && number == std::round(number))) {
      throw InputError(SourceLocation{table_path.string(), static_cast<int>(t.lines[row]), 0}, "run",
                       std::to_string(number),
                       "a run's number, 1 to " + std::to_string(declared.size()) + " (the [[run]] tables of " + path +
                           ", in order)");
    }
    const auto index = static_cast<std::size_t>(number) - 1;
    const DeclaredRun& d = declared[index];
    estimators::BalancingRun run{d.name, {}, d.masses, d.check, index};
    for (std::size_t s = 0; s < c.sensors.size(); ++s) {
      const double amplitude = t.at(c.sensors[s] + ".amplitude")[row] / amplitude_factor;
      const double phase = t.at(c.sensors[s] + ".phase")[row];
      run.readings.push_back(std::polar(amplitude, (lead ? -phase : phase) + columns[s].angle));
    }
    c.runs.push_back(std::move(run));
  }
  return c;
}

}  // namespace poise::balancing
