#include "kinds/geometry_mass_properties/geometry_mass_study.h"

#include <tbb/task_arena.h>
#include <Eigen/Eigenvalues>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <span>
#include <sstream>
#include <utility>

#include "core/format.h"
#include "core/units.h"
#include "engine/kind_interface/output_spec.h"
#include "engine/kind_interface/procedure_study.h"
#include "engine/results/result_io.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "geometry_studies/geometry_plots.h"
#include "geometry_studies/sampled_model_study.h"
#include "kinds/geometry_mass_properties/mass_properties_sections.h"
#include "model_files/disk_geometry_model.h"
#include "sampling/design.h"

namespace poise::kinds::geometry_mass_properties {
using namespace poise::engine;
using namespace poise::model_files;
using namespace poise::geometry_studies;
namespace {
namespace fs = std::filesystem;
using geometry::MassProperties;
using nlohmann::json;

constexpr OutputDeclaration kOutputs[] = {
    {"mass_g", "g", "mass of the disk with its clump weights (ray cast)"},
    {"e_um", "um", "eccentricity: centre of mass from the disk axis (ray cast)"},
    {"eps_deg", "deg", "direction of the centre of mass in the disk frame (ray cast)"},
    {"unbalance_gmm", "g*mm", "static unbalance m e (ray cast)"},
    {"Jzz_kgm2", "kg*m^2", "moment of inertia about the disk axis through the centre of mass"},
    {"Jxx_kgm2", "kg*m^2", "moment of inertia about x through the centre of mass"},
    {"Jyy_kgm2", "kg*m^2", "moment of inertia about y through the centre of mass"},
    {"axis_tilt_arcmin", "arcmin", "principal axis nearest z against z (couple unbalance)"},
    {"e_exact_um", "um", "eccentricity by the divergence theorem (exact for the mesh)"},
    {"e_ray_error_um", "um", "ray-cast e minus exact e"},
    {"mass_ray_error_pct", "%", "ray-cast mass against exact, relative"},
};

double axis_tilt(const Eigen::Matrix3d& inertia) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(inertia);
  double best = 0.0;
  for (int k = 0; k < 3; ++k) best = std::max(best, std::abs(es.eigenvectors().col(k).z()));
  return std::acos(std::min(1.0, best));
}

// Sample i: the design point -> the disk as built (DiskSampler) -> its mesh -> mass properties by
// ray casting and by the divergence theorem. No randomness of its own; no solver.
class MassStudy final : public SampledModelStudy<MassStudy> {
 public:
  MassStudy(StudyConfig cfg, DiskGeometryModel model, std::size_t n, std::uint64_t seed)
      : cfg_(std::move(cfg)),
        model_(std::move(model)),
        sampler_(model_),
        samples_(n),
        design_(make_design(cfg_, seed, n, sampler_.dimension())) {
    for (const auto& c : sampler_.columns()) declare_input({c.name, c.unit, "", ""});
    std::vector<OutputSpec> outputs;
    for (const auto& o : kOutputs) outputs.push_back({o.name, o.unit, o.description});
    declare_outputs(std::move(outputs));
  }

  const StudyConfig& config() const override { return cfg_; }
  std::string model_name() const override { return model_.name; }
  std::string model_source() const override { return model_.source; }
  std::size_t samples() const { return samples_; }
  const DiskGeometryModel& model() const { return model_; }
  const DiskSampler& sampler() const { return sampler_; }

  const sampling::Design& design() const { return design_; }
  /// What the sampler draws for these inputs (SI).
  auto realization_of(std::span<const double> si) const { return sampler_.spec_of(si); }

  geometry::Moments ray(const geometry::Assembly& parts, int n) const {
    if (mass_properties_sections(cfg_).per_part) return geometry::raycast_moments(parts, {2, n});
    std::vector<geometry::Mesh> meshes;
    std::vector<double> rho;
    for (const auto& b : parts) meshes.push_back(b.mesh), rho.push_back(b.density);
    const geometry::EmbreeScene scene(std::move(meshes), true);
    return geometry::raycast_moments(scene, rho, {2, n});
  }

  /// The outputs of one disk as built; throws poise::Error for a non-finite property.
  std::vector<double> outputs_of(const geometry::DiskSpec& spec) const {
    const geometry::Assembly parts = geometry::simulator_disk(spec);
    const MassProperties r = geometry::to_mass_properties(ray(parts, mass_properties_sections(cfg_).rays_per_side));
    const MassProperties x = geometry::to_mass_properties(geometry::exact_moments(parts));
    const double e = std::hypot(r.com.x(), r.com.y()), ex = std::hypot(x.com.x(), x.com.y());
    std::vector<double> outputs{r.mass * 1e3,
                                e * 1e6,
                                std::atan2(r.com.y(), r.com.x()) / units::kRadPerDeg,
                                r.mass * e * 1e6,
                                r.inertia(2, 2),
                                r.inertia(0, 0),
                                r.inertia(1, 1),
                                axis_tilt(r.inertia) / units::kRadPerDeg * 60.0,
                                ex * 1e6,
                                (e - ex) * 1e6,
                                (r.mass / x.mass - 1) * 100};
    for (double v : outputs) {
      if (!std::isfinite(v)) throw Error("non-finite mass property");
    }
    return outputs;
  }

  nlohmann::json details(const McResult&) const override;
  void report_sections(const McResult& mc, const std::string& plots_dir, bool plots, std::vector<std::string>& figures,
                       std::ostringstream& html) const override;

 private:
  // The nominal disk against its closed form, and the ray integration's convergence with ray
  // density: made once, for summary.json and the report.
  const nlohmann::json& nominal_check() const;

  StudyConfig cfg_;
  DiskGeometryModel model_;
  DiskSampler sampler_;
  std::size_t samples_;
  sampling::Design design_;
  mutable nlohmann::json nominal_check_;  // null until nominal_check() (rank 0, after the run)
};

// Closed form of the nominal disk: cylinder minus 16 through holes plus clump cylinders on top.
json closed_form_check(const DiskGeometryModel& m, const MassProperties& exact, const MassProperties& ray) {
  const geometry::DiskSpec& s = m.nominal;
  const double pi = std::numbers::pi, t = s.thickness;
  const double md = s.density * pi * s.radius * s.radius * t;
  double mass = md, jz = md * s.radius * s.radius / 2;
  Eigen::Vector3d first(0, 0, md * t / 2);
  for (const auto& h : s.holes) {
    const double r = h.diameter / 2, mh = s.density * pi * r * r * t;
    mass -= mh;
    first -= mh * Eigen::Vector3d(h.radius * std::cos(h.angle), h.radius * std::sin(h.angle), t / 2);
    jz -= mh * (r * r / 2 + h.radius * h.radius);
  }
  for (const auto& c : s.clumps) {
    const auto& h = s.holes[c.hole];
    const double r = c.diameter / 2, len = c.mass / (c.density * pi * r * r);
    mass += c.mass;
    first += c.mass * Eigen::Vector3d(h.radius * std::cos(h.angle), h.radius * std::sin(h.angle), t + len / 2);
    jz += c.mass * (r * r / 2 + h.radius * h.radius);
  }
  const Eigen::Vector3d com = first / mass;
  const double e = std::hypot(com.x(), com.y());
  const double jz_com = jz - mass * (com.x() * com.x() + com.y() * com.y());
  auto row = [](double closed, double v) {
    return json{{"closed_form", closed}, {"value", v}, {"relative_error", v / closed - 1}};
  };
  return {
      {"mass_kg", {{"exact_mesh", row(mass, exact.mass)}, {"ray_cast", row(mass, ray.mass)}}},
      {"e_m",
       {{"exact_mesh", row(e, std::hypot(exact.com.x(), exact.com.y()))},
        {"ray_cast", row(e, std::hypot(ray.com.x(), ray.com.y()))}}},
      {"Jzz_kgm2", {{"exact_mesh", row(jz_com, exact.inertia(2, 2))}, {"ray_cast", row(jz_com, ray.inertia(2, 2))}}}};
}

const json& MassStudy::nominal_check() const {
  if (!nominal_check_.is_null()) return nominal_check_;
  const MassPropertiesSections& g = mass_properties_sections(cfg_);
  const geometry::Assembly nominal = geometry::simulator_disk(model_.nominal);
  const MassProperties exact = geometry::to_mass_properties(geometry::exact_moments(nominal));
  const MassProperties ray_nominal = geometry::to_mass_properties(ray(nominal, g.rays_per_side));
  json convergence = json::array();
  const double e_exact = std::hypot(exact.com.x(), exact.com.y());
  const int threads = tbb::this_task_arena::max_concurrency();
  for (int k : g.convergence) {
    geometry::RayCastStats st;
    MassProperties p;
    const auto c0 = std::chrono::steady_clock::now();
    if (g.per_part) {
      p = geometry::to_mass_properties(geometry::raycast_moments(nominal, {2, k}, &st));
    } else {
      p = geometry::to_mass_properties(ray(nominal, k));
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
    const double em = std::abs(p.mass / exact.mass - 1), ej = std::abs(p.inertia(2, 2) / exact.inertia(2, 2) - 1);
    const double ee = e_exact > 0 ? std::abs(std::hypot(p.com.x(), p.com.y()) / e_exact - 1) : 0.0;
    convergence.push_back({{"rays_per_side", k},
                           {"rays", st.rays},
                           {"mass_rel_error", em},
                           {"Jzz_rel_error", ej},
                           {"e_rel_error", ee},
                           {"seconds", secs},
                           {"threads", threads}});
  }
  nominal_check_ = {
      {"method",
       {{"rays_per_side", g.rays_per_side},
        {"grid", g.per_part ? "per_part" : "one_scene"},
        {"integration", "Embree all-hit ray casting, winding-weighted segments integrated analytically"}}},
      {"nominal",
       {{"mass_kg", exact.mass},
        {"com_m", {exact.com.x(), exact.com.y(), exact.com.z()}},
        {"inertia_kgm2",
         {{exact.inertia(0, 0), exact.inertia(0, 1), exact.inertia(0, 2)},
          {exact.inertia(1, 0), exact.inertia(1, 1), exact.inertia(1, 2)},
          {exact.inertia(2, 0), exact.inertia(2, 1), exact.inertia(2, 2)}}},
        {"closed_form_check", closed_form_check(model_, exact, ray_nominal)}}},
      {"convergence", convergence}};
  return nominal_check_;
}

json MassStudy::details(const McResult&) const { return nominal_check(); }

// The report's own sections: the nominal disk against its closed form, the ray integration's
// convergence, and the figures of the disks as built.
void MassStudy::report_sections(const McResult& mc, const std::string& plots_dir, bool plots, std::vector<std::string>&,
                                std::ostringstream& h) const {
  const json& check = nominal_check();
  const MassPropertiesSections& g = mass_properties_sections(cfg_);
  h << "<h2>Nominal disk against its closed form</h2>\n<table><tr><th class='l'>quantity</th><th>closed form</th>"
    << "<th>divergence theorem (mesh)</th><th>rel. error</th><th>ray cast (" << g.rays_per_side
    << " per side)</th><th>rel. error</th></tr>\n";
  for (const auto& [name, q] : check["nominal"]["closed_form_check"].items()) {
    h << "<tr><td class='l'>" << name << "</td><td>" << significant(q["exact_mesh"]["closed_form"].get<double>(), 7)
      << "</td><td>" << significant(q["exact_mesh"]["value"].get<double>(), 7) << "</td><td>"
      << significant(q["exact_mesh"]["relative_error"].get<double>(), 3) << "</td><td>"
      << significant(q["ray_cast"]["value"].get<double>(), 7) << "</td><td>"
      << significant(q["ray_cast"]["relative_error"].get<double>(), 3) << "</td></tr>\n";
  }
  h << "</table>\n<p><small>The mesh's circles are polygons of equal area, so the mesh's mass equals the drawing's; "
       "the polygons' inertia differs by O(n<sup>-4</sup>).</small></p>\n";
  h << "<h2>Convergence of the ray-cast integration (nominal disk)</h2>\n<table><tr><th>rays per side</th><th>rays</th>"
    << "<th>|mass error|</th><th>|J<sub>zz</sub> error|</th><th>|e error|</th><th>seconds</th></tr>\n";
  std::ostringstream conv_dat;
  conv_dat << "# rays_per_side  |mass err|  |Jzz err|  |e err| (relative, vs exact mesh)  seconds\n";
  for (const auto& c : check["convergence"]) {
    h << "<tr><td>" << c["rays_per_side"].get<int>() << "</td><td>" << c["rays"].get<std::size_t>() << "</td><td>"
      << significant(c["mass_rel_error"].get<double>(), 3) << "</td><td>"
      << significant(c["Jzz_rel_error"].get<double>(), 3) << "</td><td>"
      << significant(c["e_rel_error"].get<double>(), 3) << "</td><td>" << significant(c["seconds"].get<double>(), 3)
      << " (" << c["threads"].get<int>() << " threads)</td></tr>\n";
    conv_dat << c["rays_per_side"].get<int>() << ' ' << c["mass_rel_error"].get<double>() << ' '
             << c["Jzz_rel_error"].get<double>() << ' ' << c["e_rel_error"].get<double>() << ' '
             << c["seconds"].get<double>() << '\n';
  }
  h << "</table>\n";
  if (g.export_mesh) {  // beside plots/, in the run folder
    const fs::path run_dir = fs::path(plots_dir).parent_path();
    const geometry::Mesh merged = geometry::merge(geometry::simulator_disk(model_.nominal), model_.name);
    write_file_atomic((run_dir / "nominal_disk.stl").string(), geometry::stl_bytes(merged, 1e-3));
    write_file_atomic((run_dir / "nominal_disk.obj").string(), geometry::obj_text(merged, 1e-3));
    h << "<p>The nominal disk's mesh: <code>nominal_disk.stl</code> and <code>nominal_disk.obj</code> (mm) in the run "
         "folder.</p>\n";
  }
  if (!plots || mc.ok_index.empty()) return;
  std::ostringstream sample_dat;
  sample_dat << "# e_um eps_deg Jzz_kgm2 axis_tilt_arcmin e_ray_error_um\n";
  for (std::size_t m = 0; m < mc.ok_index.size(); ++m) {
    sample_dat << mc.values[1][m] << ' ' << mc.values[2][m] << ' ' << mc.values[4][m] << ' ' << mc.values[7][m] << ' '
               << mc.values[9][m] << '\n';
  }
  std::vector<GeometryPlot> figures;
  figures.push_back(
      {"convergence", conv_dat.str(),
       "set title 'Ray-cast integration against the divergence theorem, nominal disk'\n"
       "set xlabel 'rays per side'\nset ylabel 'relative error'\nset logscale xy\nset key top right\n"
       "plot 'convergence.dat' u 1:2 w lp lw 2 t 'mass', '' u 1:3 w lp lw 2 t 'J_zz', '' u 1:4 w lp lw 2 t 'e', "
       "1e-3 w l dt 2 lc rgb 'red' t '0.1%'\n",
       "Relative error of the ray-cast mass, J_zz and eccentricity against the exact mesh values"});
  figures.push_back({"hist_e", sample_dat.str(),
                     histogram_script("hist_e.dat", 1, "Eccentricity of the as-built disk", "e [um]"),
                     "Eccentricity e of the as-built disk over the samples"});
  figures.push_back(
      {"polar_e", sample_dat.str(),
       "set title 'Centre of mass of the as-built disks (disk frame)'\nset xlabel 'x [um]'\nset ylabel 'y [um]'\n"
       "set size ratio -1\nplot 'polar_e.dat' u ($1*cos($2*pi/180)):($1*sin($2*pi/180)) w p pt 7 ps 0.4 notitle\n",
       "Centre of mass in the disk plane, one point per sample"});
  figures.push_back({"hist_jzz", sample_dat.str(),
                     histogram_script("hist_jzz.dat", 3, "J_zz about the centre of mass", "J_zz [kg m^2]"),
                     "Moment of inertia about the disk axis over the samples"});
  figures.push_back({"hist_ray_error", sample_dat.str(),
                     histogram_script("hist_ray_error.dat", 5, "Ray-cast e minus exact e", "error [um]"),
                     "Error of the ray-cast eccentricity against the divergence theorem, per sample"});
  h << "<h2>The disks as built</h2>\n" << geometry_figures_html(plots_dir, figures);
}

}  // namespace

std::unique_ptr<ProcedureStudy> make_geometry_mass_study(const StudyConfig& cfg,
                                                         const std::map<std::string, std::string>& model_overrides,
                                                         std::size_t samples, std::uint64_t seed) {
  return std::make_unique<MassStudy>(cfg, load_disk_geometry_model(cfg.model_path, model_overrides), samples, seed);
}

std::string validate_geometry_mass_study(const StudyConfig& cfg) {
  const MassStudy study(cfg, load_disk_geometry_model(cfg.model_path, cfg.overrides), cfg.samples, cfg.seed);
  const auto& s = study.model().nominal;
  const MassPropertiesSections& g = mass_properties_sections(cfg);
  return cfg.file + ": valid. Study '" + cfg.name + "' (" + cfg.kind + ") on model '" + study.model().name +
         "': disk " + significant(2e3 * s.radius, 6) + " mm x " + significant(1e3 * s.thickness, 6) + " mm, " +
         std::to_string(s.holes.size()) + " holes, " + std::to_string(s.clumps.size()) + " clump weight(s); " +
         std::to_string(study.sampler().dimension()) + " random inputs, " + sampling::to_string(cfg.method) +
         " design, " + std::to_string(cfg.samples) + " samples, seed " + std::to_string(cfg.seed) + "; rays " +
         std::to_string(g.rays_per_side) + " per side (" + (g.per_part ? "one grid per part" : "one scene") + ").";
}

}  // namespace poise::kinds::geometry_mass_properties
