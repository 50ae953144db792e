#include "studies/gimbal_runner.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>

#include "core/units.h"
#include "core/version.h"
#include "studies/gimbal_study.h"
#include "studies/provenance.h"
#include "studies/result_io.h"
#include "studies/report.h"

namespace poise::studies {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string fmt(double v, int prec = 9) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

std::string unit_of(const std::string& name) {
  for (const char* u : {"mNm", "deg", "gmm"}) {
    const std::string suffix = std::string("_") + u;
    if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      return std::string(u) == "mNm" ? "mN*m" : std::string(u) == "gmm" ? "g*mm" : "deg";
    }
  }
  return "";
}


}  // namespace

std::string validate_gimbal_study(const StudyConfig& cfg) {
  const GimbalModel model = load_gimbal_model(cfg.model_path, cfg.overrides);
  GimbalStudy study(cfg, model, cfg.samples, cfg.seed);
  std::size_t tests = 0, positions = 0;
  for (const auto& g : cfg.groups) {
    tests += g.repeats * g.loads.size();
    positions += g.repeats * g.loads.size() * g.positions;
  }
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s: valid. Study '%s' (%s) on model '%s': %zu unit-scope random inputs, %s design, %zu "
                "samples, seed %llu; per sample %zu group(s), %zu simulated tests, %zu turntable positions.",
                cfg.file.c_str(), cfg.name.c_str(), cfg.kind.c_str(), model.name.c_str(), study.input_names().size(),
                sampling::to_string(cfg.method).c_str(), cfg.samples, static_cast<unsigned long long>(cfg.seed),
                cfg.groups.size(), tests, positions);
  return buf;
}

json replay_gimbal_sample(const StudyConfig& cfg, std::size_t index, const RunOptions& options) {
  const std::size_t n = options.samples.value_or(cfg.samples);
  if (index >= n) throw Error("sample index " + std::to_string(index) + " is outside 0.." + std::to_string(n - 1));
  GimbalStudy study(cfg, load_gimbal_model(cfg.model_path, cfg.overrides), n, options.seed.value_or(cfg.seed));
  auto ws = study.make_workspace();
  GimbalSampleResult r;
  study.compute(index, *ws, r);
  json j{{"sample", index}, {"status", r.ok ? "ok" : "failed"}};
  if (!r.ok) j["message"] = r.message;
  for (std::size_t k = 0; k < r.inputs.size(); ++k) j["inputs"][study.input_names()[k]] = r.inputs[k];
  for (std::size_t k = 0; k < r.outputs.size(); ++k) j["outputs"][study.output_names()[k]] = r.outputs[k];
  return j;
}

namespace {

// Samples already in an interrupted run's samples.csv: complete lines only, in order from
// 0; a partial last line is cut off the file. Throws if the header is not this study's.
std::vector<GimbalSampleResult> read_done_samples(const std::string& csv_path, const std::string& header,
                                                  std::size_t n_inputs, std::size_t n_outputs) {
  std::ifstream in(csv_path, std::ios::binary);
  if (!in) throw Error("--resume: cannot read " + csv_path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const std::size_t complete = text.rfind('\n');
  if (complete == std::string::npos || text.compare(0, header.size() + 1, header + "\n") != 0) {
    throw Error("--resume: " + csv_path + " does not start with this study's header");
  }
  if (complete + 1 != text.size()) {  // cut the partial line an interruption left
    text.resize(complete + 1);
    std::ofstream(csv_path, std::ios::binary | std::ios::trunc) << text;
  }
  std::vector<GimbalSampleResult> done;
  std::istringstream lines(text.substr(header.size() + 1));
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    if (cells.size() != 2 + n_inputs + n_outputs + 2) {
      throw Error("--resume: " + csv_path + " row " + std::to_string(done.size() + 2) + " has " +
                  std::to_string(cells.size()) + " cells, expected " + std::to_string(4 + n_inputs + n_outputs));
    }
    GimbalSampleResult r;
    r.index = std::stoul(cells[0]);
    if (r.index != done.size()) throw Error("--resume: samples.csv rows are not in order at sample " + cells[0]);
    r.ok = cells[1] == "ok";
    for (std::size_t k = 0; k < n_inputs; ++k) r.inputs.push_back(std::stod(cells[2 + k]));
    for (std::size_t k = 0; k < n_outputs; ++k) r.outputs.push_back(std::stod(cells[2 + n_inputs + k]));
    r.solver_steps = std::stol(cells[2 + n_inputs + n_outputs]);
    r.message = cells.back();
    done.push_back(std::move(r));
  }
  return done;
}

}  // namespace

std::string run_gimbal_study(const StudyConfig& cfg, const RunOptions& options) {
  const GimbalModel model = load_gimbal_model(cfg.model_path, cfg.overrides);
  std::size_t n = options.samples.value_or(cfg.samples);
  std::uint64_t seed = options.seed.value_or(cfg.seed);
  const int threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::string dir;
  json manifest;
  if (!options.resume.empty()) {
    dir = options.resume;
    std::ifstream mf(fs::path(dir) / "run.json");
    if (!mf) throw Error("--resume " + dir + ": no run.json there (not a run folder of Poise)");
    manifest = json::parse(mf);
    if (manifest.value("study_file_sha1", "") != file_sha1(cfg.file) ||
        manifest.value("model_file_sha1", "") != file_sha1(cfg.model_path)) {
      throw Error("--resume " + dir + ": the study or model file changed since the run began; start a new run");
    }
    n = manifest.at("samples").get<std::size_t>();
    seed = manifest.at("seed").get<std::uint64_t>();
  } else {
    dir = make_run_folder(options.results_root, cfg.name, options.out);
    manifest = {{"kind", cfg.kind}, {"study_file_sha1", file_sha1(cfg.file)},
                {"model_file_sha1", file_sha1(cfg.model_path)}, {"samples", n}, {"seed", seed},
                {"method", sampling::to_string(cfg.method)}, {"poise_version", kVersion}, {"started", now_iso8601()}};
    std::ofstream(fs::path(dir) / "run.json") << manifest.dump(2) << '\n';
  }
  const std::string started = manifest.value("started", now_iso8601());
  if (options.progress) {
    std::fprintf(stderr, "poise: study %s -> %s\n  %zu samples (%s, seed %llu) on %d thread(s)\n", cfg.name.c_str(),
                 dir.c_str(), n, sampling::to_string(cfg.method).c_str(), static_cast<unsigned long long>(seed), threads);
  }
  GimbalStudy study(cfg, model, n, seed);
  std::string header = "sample,status";
  for (const auto& c : study.input_names()) header += "," + c;
  for (const auto& c : study.output_names()) header += "," + c;
  header += ",solver_steps,message";
  const std::string csv_path = (fs::path(dir) / "samples.csv").string();
  std::vector<GimbalSampleResult> done;
  if (!options.resume.empty()) {
    done = read_done_samples(csv_path, header, study.input_names().size(), study.output_names().size());
    if (options.progress) std::fprintf(stderr, "  resuming: %zu of %zu samples already done\n", done.size(), n);
  }
  std::ofstream csv(csv_path, options.resume.empty() ? std::ios::trunc : std::ios::app);
  if (!csv) throw Error("cannot write " + csv_path);
  if (options.resume.empty()) csv << header << '\n';
  const GimbalMcResult mc = study.run(threads, options.progress, [&](std::span<const GimbalSampleResult> block) {
    for (const auto& s : block) {
      csv << s.index << ',' << (s.ok ? "ok" : "failed");
      for (double v : s.inputs) csv << ',' << csv_number(v);
      for (double v : s.outputs) csv << ',' << csv_number(v);
      csv << ',' << s.solver_steps << ',' << csv_text(s.message) << '\n';
    }
    csv.flush();
  }, done);
  csv.close();

  json s;
  s["study"] = {{"name", cfg.name}, {"title", cfg.title}, {"kind", cfg.kind}, {"file", cfg.file},
                {"model_file", cfg.model_path}, {"model_name", model.name}, {"model_source", model.source},
                {"notes", cfg.notes}, {"overrides", cfg.overrides}};
  s["sampling"] = {{"method", sampling::to_string(cfg.method)}, {"samples", n}, {"seed", seed}, {"threads", threads},
                   {"inputs", study.input_names()},
                   {"ci_note", "95% intervals assume independent samples; for lhs and sobol designs they are conservative"}};
  json outputs;
  for (std::size_t k = 0; k < mc.outputs.size(); ++k) {
    json o = summary_json(mc.outputs[k]);
    o["unit"] = unit_of(study.output_names()[k]);
    outputs[study.output_names()[k]] = o;
  }
  s["outputs"] = outputs;
  // The paper's figures beside the simulated distribution: where the paper's value falls.
  json cmp = json::array();
  for (std::size_t gi = 0; gi < cfg.groups.size(); ++gi) {
    const auto& g = cfg.groups[gi];
    auto add = [&](const std::string& out, std::optional<double> paper, double factor, const char* unit) {
      if (!paper || mc.outputs.empty()) return;
      std::size_t k = 0;
      while (k < study.output_names().size() && study.output_names()[k] != g.name + "_" + out) ++k;
      const auto& v = mc.values[k];
      const double p = *paper / factor;
      std::size_t below = 0;
      for (double x : v) below += x <= p ? 1 : 0;
      cmp.push_back({{"group", g.name}, {"figure", out}, {"unit", unit}, {"paper", p},
                     {"simulated", summary_json(mc.outputs[k])},
                     {"paper_percentile", static_cast<double>(below) / static_cast<double>(v.size())}});
    };
    add("rmse_torque_mNm", g.paper_rmse_torque, 1e-3, "mN*m");
    add("rmse_angle_deg", g.paper_rmse_angle, units::kRadPerDeg, "deg");
  }
  s["paper_comparison"] = cmp;
  s["failures"] = {{"count", mc.failures}, {"first", json::array()}};
  for (const auto& [i, why] : mc.failed) s["failures"]["first"].push_back({{"sample", i}, {"reason", why}});
  s["solver"] = {{"steps", mc.solver_steps}, {"rhs_evals", mc.rhs_evals}, {"rtol", model.plan.solver.rtol},
                 {"max_order", model.plan.solver.max_order}};
  s["provenance"] = {{"poise_version", kVersion}, {"git_commit", git_commit()},
                     {"study_file_sha1", file_sha1(cfg.file)}, {"model_file_sha1", file_sha1(cfg.model_path)},
                     {"seed", seed}, {"samples", n}, {"threads", threads}, {"wall_time_s", mc.wall_seconds},
                     {"started", started}, {"finished", now_iso8601()}, {"libraries", library_versions()},
                     {"resumed_after_sample", options.resume.empty() ? json(nullptr) : json(done.size())}};
  {
    std::ofstream js(fs::path(dir) / "summary.json");
    js << s.dump(2) << '\n';
  }

  // Plots: one histogram per compared figure, with the paper's value as a line.
  const fs::path pdir = fs::path(dir) / "plots";
  fs::create_directories(pdir);
  std::vector<std::string> figures;
  std::string plot_note;
  if (options.plots && cfg.plots && !mc.outputs.empty()) {
    int fi = 0;
    for (const auto& c : cmp) {
      const std::string name = c["group"].get<std::string>() + "_" + c["figure"].get<std::string>();
      std::size_t k = 0;
      while (study.output_names()[k] != name) ++k;
      {
        std::ofstream d(pdir / (name + ".dat"));
        for (double v : mc.values[k]) d << v << '\n';
      }
      const double paper = c["paper"].get<double>();
      std::ostringstream g;
      g << "set terminal svg size 640,400 dynamic noenhanced font 'Helvetica,12'\nset output '" << name << ".svg'\n"
        << "set title '" << name << ": simulated campaigns vs the paper'\nset xlabel '" << c["unit"].get<std::string>()
        << "'\nset ylabel 'campaigns'\nstats '" << name << ".dat' u 1 nooutput\n"
        << "bw = (STATS_max - STATS_min) / 20.0\nif (bw <= 0) bw = 0.01\nbin(x) = bw * floor(x / bw) + bw / 2\n"
        << "set style fill solid 0.6\nset arrow from " << paper << ", graph 0 to " << paper
        << ", graph 1 nohead lw 2 lc rgb 'red'\nset label 'paper' at " << paper << ", graph 0.95 offset 0.5,0 tc rgb 'red'\n"
        << "set xrange [0:*]\nplot '" << name << ".dat' u (bin($1)):(1.0) smooth freq with boxes lc rgb '#4477aa' title 'simulated'\n";
      std::ofstream(pdir / (name + ".gp")) << g.str();
      std::string why;
      if (run_gnuplot((pdir / (name + ".gp")).string(), &why)) {
        figures.push_back(name + ".svg");
      } else {
        plot_note = why;
      }
      ++fi;
    }
  }
  // Report.
  std::ostringstream h;
  h << "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>Poise: " << html_escape(cfg.name)
    << "</title><style>body{font-family:Helvetica,Arial,sans-serif;max-width:1100px;margin:2em auto;color:#222}"
       "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
       "th{background:#eef}td.l,th.l{text-align:left}small{color:#666}pre{background:#f6f6f6;padding:0.8em;"
       "white-space:pre-wrap}</style></head><body>\n<h1>"
    << html_escape(cfg.title.empty() ? cfg.name : cfg.title) << "</h1>\n<p>Study <code>" << html_escape(cfg.file) << "</code>, model <code>"
    << html_escape(cfg.model_path) << "</code> (" << html_escape(model.source) << "). " << n << " simulated campaigns ("
    << sampling::to_string(cfg.method) << ", seed " << seed << "), " << mc.failures << " failed.</p>\n";
  auto cell = [](const json& e) {
    std::string out = fmt(e["value"].get<double>(), 4) + " <small>[";
    out += e["ci95"][0].is_number() ? fmt(e["ci95"][0].get<double>(), 4) : std::string("&ndash;");
    out += ", ";
    out += e["ci95"][1].is_number() ? fmt(e["ci95"][1].get<double>(), 4) : std::string("&ndash;");
    return out + "]</small>";
  };
  if (!cmp.empty()) {
    h << "<h2>The paper against the simulation</h2>\n<table><tr><th class='l'>group</th><th class='l'>figure</th>"
         "<th>paper</th><th>simulated p50</th><th>simulated mean</th><th>p95</th><th>paper's percentile</th></tr>\n";
    for (const auto& c : cmp) {
      h << "<tr><td class='l'>" << html_escape(c["group"].get<std::string>()) << "</td><td class='l'>"
        << html_escape(c["figure"].get<std::string>()) << "</td><td>" << fmt(c["paper"].get<double>(), 4) << "</td><td>"
        << cell(c["simulated"]["p50"]) << "</td><td>" << cell(c["simulated"]["mean"]) << "</td><td>"
        << cell(c["simulated"]["p95"]) << "</td><td>" << fmt(100 * c["paper_percentile"].get<double>(), 3) << "%</td></tr>\n";
    }
    h << "</table>\n<p><small>A paper figure between the 2.5th and 97.5th percentiles of the simulated "
         "campaigns is what the model expects; outside, the model misses an effect or a value.</small></p>\n";
  }
  h << "<h2>Outputs per campaign</h2>\n<table><tr><th class='l'>output</th><th>mean</th><th>std</th><th>p50</th>"
       "<th>p95</th><th>p99.73</th><th>max</th></tr>\n";
  for (const auto& [name, o] : s["outputs"].items()) {
    h << "<tr><td class='l'><code>" << html_escape(name) << "</code> " << html_escape(o["unit"].get<std::string>()) << "</td><td>"
      << cell(o["mean"]) << "</td><td>" << cell(o["std"]) << "</td><td>" << cell(o["p50"]) << "</td><td>"
      << cell(o["p95"]) << "</td><td>" << cell(o["p99_73"]) << "</td><td>" << cell(o["max"]) << "</td></tr>\n";
  }
  h << "</table>\n<h2>Figures</h2>\n";
  if (!plot_note.empty()) h << "<p>" << html_escape(plot_note) << "</p>\n";
  for (const auto& f : figures) h << "<p><img src='plots/" << f << "' alt='" << f << "'></p>\n";
  if (!cfg.notes.empty()) h << "<h2>Notes of the study</h2>\n<pre>" << html_escape(cfg.notes) << "</pre>\n";
  h << "<h2>Provenance</h2>\n<pre>" << html_escape(s["provenance"].dump(2)) << "\n" << html_escape(s["solver"].dump(2))
    << "</pre>\n</body></html>\n";
  std::ofstream(fs::path(dir) / "report.html") << h.str();
  if (options.progress) std::fprintf(stderr, "poise: report %s\n", (fs::path(dir) / "report.html").c_str());
  return dir;
}

}  // namespace poise::studies
