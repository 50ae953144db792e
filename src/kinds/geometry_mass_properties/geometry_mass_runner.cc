#include "kinds/geometry_mass_properties/geometry_mass_runner.h"

#include <Eigen/Eigenvalues>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <span>
#include <utility>

#include "core/units.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "sampling/design.h"
#include "model_files/disk_geometry_model.h"
#include "geometry_studies/geometry_runner_common.h"
#include "engine/result_io.h"
#include "engine/study_kind.h"
#include "geometry_studies/geometry_study.h"

namespace poise::studies {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using geometry::MassProperties;

constexpr GeometryOutputDef kOutputs[] = {
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
constexpr std::size_t kNumOutputs = std::size(kOutputs);

double axis_tilt(const Eigen::Matrix3d& inertia) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(inertia);
  double best = 0.0;
  for (int k = 0; k < 3; ++k) best = std::max(best, std::abs(es.eigenvectors().col(k).z()));
  return std::acos(std::min(1.0, best));
}

class MassStudy {
 public:
  MassStudy(const StudyConfig& cfg, std::size_t n, std::uint64_t seed)
      : cfg_(cfg), model_(load_disk_geometry_model(cfg.model_path, cfg.overrides)), sampler_(model_),
        design_(make_design(cfg, seed, n, sampler_.dimension())) {}

  const DiskGeometryModel& model() const { return model_; }
  const DiskSampler& sampler() const { return sampler_; }

  geometry::Moments ray(const geometry::Assembly& parts, int n) const {
    if (geometry_sections(cfg_).geometry.per_part) return geometry::raycast_moments(parts, {2, n});
    std::vector<geometry::Mesh> meshes;
    std::vector<double> rho;
    for (const auto& b : parts) meshes.push_back(b.mesh), rho.push_back(b.density);
    const geometry::EmbreeScene scene(std::move(meshes), true);
    return geometry::raycast_moments(scene, rho, {2, n});
  }

  void compute(std::size_t i, GeometrySample& out) const {
    compute_geometry_sample(i, design_, sampler_.dimension(), kNumOutputs, out,
                            [&](std::span<const double> u, std::vector<double>& inputs) {
      return outputs_of(sampler_.draw(u, inputs));
    });
  }

  /// The outputs of one disk as built; throws poise::Error for a non-finite property.
  std::vector<double> outputs_of(const geometry::DiskSpec& spec) const {
      const geometry::Assembly parts = geometry::simulator_disk(spec);
      const MassProperties r = geometry::to_mass_properties(ray(parts, geometry_sections(cfg_).geometry.rays_per_side));
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

 private:
  const StudyConfig& cfg_;
  DiskGeometryModel model_;
  DiskSampler sampler_;
  sampling::Design design_;
};

// At given inputs (the hole, clump, thickness and wedge deviations: the disk itself): the same
// mass properties as a drawn sample's. No randomness of its own.
class MassInputEvaluator final : public InputEvaluator {
 public:
  explicit MassInputEvaluator(StudyConfig cfg) : cfg_(std::move(cfg)), study_(cfg_, 1, cfg_.seed) {
    for (const auto& c : study_.sampler().columns()) {
      names_.push_back(c.name);
      factors_.push_back(c.display_factor);
    }
    for (const auto& o : kOutputs) outputs_.push_back({o.name, o.unit, o.description});
  }
  const std::vector<std::string>& input_names() const override { return names_; }
  const std::vector<OutputSpec>& outputs() const override { return outputs_; }
  std::vector<double> nominal_inputs() const override { return study_.sampler().nominal(); }
  void evaluate_points(const InputColumns& inputs, double* values, std::size_t begin, std::size_t end,
                       std::vector<std::pair<std::size_t, std::string>>& failures) const override {
    evaluate_each_point(inputs, factors_, names_.size(), kNumOutputs, values, begin, end, failures,
                        [&](std::size_t, std::span<const double> si, std::span<double> y) {
                          const std::vector<double> o = study_.outputs_of(study_.sampler().spec_of(si));
                          std::copy(o.begin(), o.end(), y.begin());
                        });
  }

 private:
  StudyConfig cfg_;  // before study_, which refers to it
  MassStudy study_;
  std::vector<std::string> names_;
  std::vector<double> factors_;
  std::vector<OutputSpec> outputs_;
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
  auto row = [](double closed, double v) { return json{{"closed_form", closed}, {"value", v}, {"relative_error", v / closed - 1}}; };
  return {{"mass_kg", {{"exact_mesh", row(mass, exact.mass)}, {"ray_cast", row(mass, ray.mass)}}},
          {"e_m", {{"exact_mesh", row(e, std::hypot(exact.com.x(), exact.com.y()))}, {"ray_cast", row(e, std::hypot(ray.com.x(), ray.com.y()))}}},
          {"Jzz_kgm2", {{"exact_mesh", row(jz_com, exact.inertia(2, 2))}, {"ray_cast", row(jz_com, ray.inertia(2, 2))}}}};
}

}  // namespace

std::unique_ptr<InputEvaluator> geometry_mass_input_evaluator(const StudyConfig& cfg,
                                                               const std::map<std::string, std::string>& model_overrides) {
  StudyConfig c = cfg;
  for (const auto& [k, v] : model_overrides) c.overrides[k] = v;
  return std::make_unique<MassInputEvaluator>(std::move(c));
}

std::vector<OutputSpec> geometry_mass_outputs() {
  std::vector<OutputSpec> out;
  for (const auto& o : kOutputs) out.push_back({o.name, o.unit, o.description});
  return out;
}

std::string validate_geometry_mass_study(const StudyConfig& cfg) {
  const MassStudy study(cfg, cfg.samples, cfg.seed);
  const auto& s = study.model().nominal;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s: valid. Study '%s' (%s) on model '%s': disk %g mm x %g mm, %zu holes, %zu clump weight(s); %zu "
                "random inputs, %s design, %zu samples, seed %llu; rays %d per side (%s).",
                cfg.file.c_str(), cfg.name.c_str(), cfg.kind.c_str(), study.model().name.c_str(), 2e3 * s.radius,
                1e3 * s.thickness, s.holes.size(), s.clumps.size(), study.sampler().dimension(),
                sampling::to_string(cfg.method).c_str(), cfg.samples, static_cast<unsigned long long>(cfg.seed),
                geometry_sections(cfg).geometry.rays_per_side, geometry_sections(cfg).geometry.per_part ? "one grid per part" : "one scene");
  return buf;
}

json replay_geometry_mass_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options) {
  const MassStudy study(cfg, geometry_replay_samples(cfg, index, options), options.seed.value_or(cfg.seed));
  GeometrySample r;
  study.compute(index, r);
  return geometry_replay_json(index, r, study.sampler().columns(), kOutputs);
}

std::string run_geometry_mass_study(const StudyConfig& study_cfg, const RunOptions& options) {
  StudyConfig cfg = study_cfg;
  const GeometryRunSize size = geometry_run_size(cfg, options, "--resume is not needed for a geometry study; it re-runs in seconds", [&] {
    return MassStudy(study_cfg, 1, study_cfg.seed).sampler().dimension();
  });
  const MassStudy study(cfg, size.samples, size.seed);
  const GeometryRun run = start_geometry_run(cfg, options, size);
  const int threads = size.threads;
  tbb::task_arena arena(threads);

  // Nominal disk: closed form, exact mesh, ray cast; convergence with ray density.
  const geometry::Assembly nominal = geometry::simulator_disk(study.model().nominal);
  const MassProperties exact = geometry::to_mass_properties(geometry::exact_moments(nominal));
  MassProperties ray_nominal;
  arena.execute([&] { ray_nominal = geometry::to_mass_properties(study.ray(nominal, geometry_sections(cfg).geometry.rays_per_side)); });
  const json closed = closed_form_check(study.model(), exact, ray_nominal);
  json convergence = json::array();
  std::ostringstream conv_dat;
  conv_dat << "# rays_per_side  |mass err|  |Jzz err|  |e err| (relative, vs exact mesh)  seconds\n";
  const double e_exact = std::hypot(exact.com.x(), exact.com.y());
  for (int k : geometry_sections(cfg).geometry.convergence) {
    geometry::RayCastStats st;
    MassProperties p;
    const auto c0 = std::chrono::steady_clock::now();
    arena.execute([&] {
      if (geometry_sections(cfg).geometry.per_part) {
        p = geometry::to_mass_properties(geometry::raycast_moments(nominal, {2, k}, &st));
      } else {
        p = geometry::to_mass_properties(study.ray(nominal, k));
      }
    });
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
    const double em = std::abs(p.mass / exact.mass - 1), ej = std::abs(p.inertia(2, 2) / exact.inertia(2, 2) - 1);
    const double ee = e_exact > 0 ? std::abs(std::hypot(p.com.x(), p.com.y()) / e_exact - 1) : 0.0;
    convergence.push_back({{"rays_per_side", k}, {"rays", st.rays}, {"mass_rel_error", em}, {"Jzz_rel_error", ej},
                           {"e_rel_error", ee}, {"seconds", secs}, {"threads", threads}});
    conv_dat << k << ' ' << em << ' ' << ej << ' ' << ee << ' ' << secs << '\n';
  }

  // Samples.
  std::ostringstream sample_dat;
  sample_dat << "# e_um eps_deg Jzz_kgm2 axis_tilt_arcmin e_ray_error_um\n";
  const GeometrySampleResults results = run_geometry_samples(
      cfg, run, study.sampler().columns(), kOutputs, [&](std::size_t i, GeometrySample& r) { study.compute(i, r); },
      [&](const GeometrySample& r) {
        sample_dat << r.outputs[1] << ' ' << r.outputs[2] << ' ' << r.outputs[4] << ' ' << r.outputs[7] << ' '
                   << r.outputs[9] << '\n';
      });

  json s;
  s["study"] = geometry_study_json(cfg, study.model().name, study.model().source);
  s["sampling"] = geometry_sampling_json(cfg, run, study.sampler().dimension());
  s["method"] = {{"rays_per_side", geometry_sections(cfg).geometry.rays_per_side},
                 {"grid", geometry_sections(cfg).geometry.per_part ? "per_part" : "one_scene"},
                 {"integration", "Embree all-hit ray casting, winding-weighted segments integrated analytically"}};
  s["nominal"] = {{"mass_kg", exact.mass},
                  {"com_m", {exact.com.x(), exact.com.y(), exact.com.z()}},
                  {"inertia_kgm2", {{exact.inertia(0, 0), exact.inertia(0, 1), exact.inertia(0, 2)},
                                    {exact.inertia(1, 0), exact.inertia(1, 1), exact.inertia(1, 2)},
                                    {exact.inertia(2, 0), exact.inertia(2, 1), exact.inertia(2, 2)}}},
                  {"closed_form_check", closed}};
  s["convergence"] = convergence;
  write_geometry_summary(s, cfg, run, kOutputs, results, study.sampler().columns());
  if (geometry_sections(cfg).geometry.export_mesh) {
    const geometry::Mesh merged = geometry::merge(nominal, study.model().name);
    write_file_atomic((fs::path(run.dir) / "nominal_disk.stl").string(), geometry::stl_bytes(merged, 1e-3));
    write_file_atomic((fs::path(run.dir) / "nominal_disk.obj").string(), geometry::obj_text(merged, 1e-3));
  }

  // Report.
  std::ostringstream t1;
  t1 << "<h2>Nominal disk against its closed form</h2>\n<table><tr><th class='l'>quantity</th><th>closed form</th>"
     << "<th>divergence theorem (mesh)</th><th>rel. error</th><th>ray cast (" << geometry_sections(cfg).geometry.rays_per_side
     << " per side)</th><th>rel. error</th></tr>\n";
  for (const auto& [name, q] : closed.items()) {
    t1 << "<tr><td class='l'>" << name << "</td><td>" << fmt_g(q["exact_mesh"]["closed_form"].get<double>(), 9) << "</td><td>"
       << fmt_g(q["exact_mesh"]["value"].get<double>(), 9) << "</td><td>" << fmt_g(q["exact_mesh"]["relative_error"].get<double>(), 3)
       << "</td><td>" << fmt_g(q["ray_cast"]["value"].get<double>(), 9) << "</td><td>"
       << fmt_g(q["ray_cast"]["relative_error"].get<double>(), 3) << "</td></tr>\n";
  }
  t1 << "</table>\n<p><small>The mesh's circles are polygons of equal area, so the mesh's mass equals the drawing's; "
        "the polygons' inertia differs by O(n<sup>-4</sup>).</small></p>\n";
  std::ostringstream t2;
  t2 << "<h2>Convergence of the ray-cast integration (nominal disk)</h2>\n<table><tr><th>rays per side</th><th>rays</th>"
     << "<th>|mass error|</th><th>|J<sub>zz</sub> error|</th><th>|e error|</th><th>seconds (" << threads
     << " threads)</th></tr>\n";
  for (const auto& c : convergence) {
    t2 << "<tr><td>" << c["rays_per_side"].get<int>() << "</td><td>" << c["rays"].get<std::size_t>() << "</td><td>"
       << fmt_g(c["mass_rel_error"].get<double>(), 3) << "</td><td>" << fmt_g(c["Jzz_rel_error"].get<double>(), 3)
       << "</td><td>" << fmt_g(c["e_rel_error"].get<double>(), 3) << "</td><td>" << fmt_g(c["seconds"].get<double>(), 3)
       << "</td></tr>\n";
  }
  t2 << "</table>\n";
  std::vector<GeometryPlot> plots;
  plots.push_back({"convergence", conv_dat.str(),
                   "set title 'Ray-cast integration against the divergence theorem, nominal disk'\n"
                   "set xlabel 'rays per side'\nset ylabel 'relative error'\nset logscale xy\nset grid\nset key top right\n"
                   "plot 'convergence.dat' u 1:2 w lp lw 2 t 'mass', '' u 1:3 w lp lw 2 t 'J_zz', '' u 1:4 w lp lw 2 t 'e', "
                   "1e-3 w l dt 2 lc rgb 'red' t '0.1%'\n",
                   "Relative error of the ray-cast mass, J_zz and eccentricity against the exact mesh values"});
  plots.push_back({"hist_e", sample_dat.str(), histogram_script("hist_e.dat", 1, "Eccentricity of the as-built disk", "e [um]"),
                   "Eccentricity e of the as-built disk over the samples"});
  plots.push_back({"polar_e", sample_dat.str(),
                   "set title 'Centre of mass of the as-built disks (disk frame)'\nset xlabel 'x [um]'\nset ylabel 'y [um]'\n"
                   "set size ratio -1\nset grid\nplot 'polar_e.dat' u ($1*cos($2*pi/180)):($1*sin($2*pi/180)) w p pt 7 ps 0.4 notitle\n",
                   "Centre of mass in the disk plane, one point per sample"});
  plots.push_back({"hist_jzz", sample_dat.str(), histogram_script("hist_jzz.dat", 3, "J_zz about the centre of mass", "J_zz [kg m^2]"),
                   "Moment of inertia about the disk axis over the samples"});
  plots.push_back({"hist_ray_error", sample_dat.str(),
                   histogram_script("hist_ray_error.dat", 5, "Ray-cast e minus exact e", "error [um]"),
                   "Error of the ray-cast eccentricity against the divergence theorem, per sample"});
  finish_geometry_report(cfg, options, run, s, {t1.str(), t2.str()}, std::move(plots), results, kOutputs);
  return run.dir;
}

}  // namespace poise::studies
