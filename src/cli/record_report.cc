#include "cli/record_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "engine/report/record_page.h"
#include "engine/report/report_plot.h"
#include "engine/results/result_io.h"

namespace poise::cli {
namespace fs = std::filesystem;
using nlohmann::json;

std::string record_answer(const json& d) {
  const std::string motion = d["motion"].value("description", "the record");
  const double before = d.value("rmse_before_mNm", 0.0), after = d.value("rmse_after_mNm", 0.0);
  const std::string drop =
      fmt::format("the torque residual RMS falls from {} to {} mN*m ({}% less)", significant(before, 4),
                  significant(after, 4), before > 0 ? std::lround(100.0 * (before - after) / before) : 0);
  std::vector<std::string> unseen;
  for (const auto& n : d.value("not_identifiable", json::array())) unseen.push_back(n.value("name", ""));
  const std::string limits =
      unseen.empty() ? "" : "; not identifiable from this motion: " + fmt::format("{}", fmt::join(unseen, ", "));
  if (d.contains("cogging_map")) {
    const json& map = d["cogging_map"];
    std::string found = map.empty() ? "no cogging order" : fmt::format("{} cogging order(s)", map.size());
    if (!map.empty()) {
      const auto top = std::max_element(map.begin(), map.end(), [](const json& a, const json& b) {
        return a["amplitude_mNm"]["value"].get<double>() < b["amplitude_mNm"]["value"].get<double>();
      });
      found += fmt::format(", the largest of order {} at {} +- {} mN*m", (*top)["order"].get<int>(),
                           significant((*top)["amplitude_mNm"]["value"].get<double>(), 4),
                           significant((*top)["amplitude_mNm"]["se"].get<double>(), 2));
    }
    if (d.contains("coulomb_mNm")) {
      found += fmt::format(", Coulomb friction {} +- {} mN*m", significant(d["coulomb_mNm"]["value"].get<double>(), 4),
                           significant(d["coulomb_mNm"]["se"].get<double>(), 2));
    }
    const std::size_t physics = d.value("outside_physics", json::array()).size();
    return fmt::format("{}: {} found; {}{}{}.", motion, found, drop, limits,
                       physics > 0 ? fmt::format("; {} estimate(s) outside physics (not findings)", physics) : "");
  }
  std::vector<std::string> effects;
  for (const auto& e : d.value("effects", json::array())) {
    effects.push_back(e.contains("order")
                          ? fmt::format("{} of order {}", e["name"].get<std::string>(), e["order"].get<int>())
                          : e["name"].get<std::string>());
  }
  return fmt::format("{}: the position's torque is {} +- {} mN*m with {}; {}.", motion,
                     significant(d["torque_after_mNm"]["value"].get<double>(), 6),
                     significant(d["torque_after_mNm"]["se"].get<double>(), 2),
                     effects.empty() ? std::string("no effect found beyond the base model")
                                     : fmt::format("the effects found ({})", fmt::join(effects, ", ")),
                     drop);
}

namespace {

// The figures' data: the map (order, amplitude, se) and the residuals against angle (at most
// 4000 points, evenly thinned: a figure, not the data, which record.json's source file holds).
std::vector<fs::path> write_figures(const fs::path& dir, const json& d, const RecordResiduals& r, std::string* note) {
  std::vector<fs::path> made;
  std::ostringstream map;
  map << "# order amplitude_mNm se_mNm\n";
  for (const auto& o : d.value("cogging_map", json::array())) {
    map << o["order"].get<int>() << ' ' << o["amplitude_mNm"]["value"].get<double>() << ' '
        << o["amplitude_mNm"]["se"].get<double>() << '\n';
  }
  for (const auto& e : d.value("effects", json::array())) {
    if (e.contains("order")) {
      map << e["order"].get<int>() << ' ' << e["params"]["amplitude"]["value"].get<double>() * 1e3 << ' '
          << e["params"]["amplitude"]["se"].get<double>() * 1e3 << '\n';
    }
  }
  engine::write_file_atomic((dir / "map.dat").string(), map.str());
  std::ostringstream res;
  res.precision(8);
  res << "# angle_deg residual_before_mNm residual_after_mNm\n";
  const std::size_t n = r.angle.size(), stride = std::max<std::size_t>(1, n / 4000);
  for (std::size_t k = 0; k < n; k += stride) {
    res << r.angle[k] * 180.0 / 3.14159265358979323846 << ' ' << r.before[k] * 1e3 << ' ' << r.after[k] * 1e3 << '\n';
  }
  engine::write_file_atomic((dir / "residual.dat").string(), res.str());
  const std::string head =
      "set terminal svg size 900,420 noenhanced font 'Helvetica,12' background rgb 'white'\n"
      "set grid\nset key below horizontal\n";
  const std::string map_gp = head +
                             "set output 'map.svg'\nset title 'Cogging map'\n"
                             "set xlabel 'order N [cycles per turn]'\nset ylabel 'amplitude T [mN*m]'\n"
                             "set xrange [0:*]\nset yrange [0:*]\nset boxwidth 0.8\nset style fill solid 0.6\n"
                             "plot 'map.dat' u 1:2 w boxes lc rgb '#1f77b4' t 'amplitude', "
                             "'map.dat' u 1:2:3 w yerrorbars pt 7 ps 0.5 lc rgb '#000000' t 'one standard error'\n";
  const std::string res_gp = head +
                             "set output 'residual.svg'\nset title 'Torque residual against angle'\n"
                             "set xlabel 'axis angle phi [deg]'\nset ylabel 'residual [mN*m]'\n"
                             "plot 'residual.dat' u 1:2 w p pt 7 ps 0.25 lc rgb '#1f77b4' t 'base model', "
                             "'residual.dat' u 1:3 w p pt 7 ps 0.25 lc rgb '#d62728' t 'with the effects found'\n";
  for (const auto& [name, script] : {std::pair{"map", map_gp}, std::pair{"residual", res_gp}}) {
    const fs::path gp = dir / (std::string(name) + ".gp");
    engine::write_file_atomic(gp.string(), script);
    std::string why;
    if (engine::run_gnuplot(gp.string(), &why) && fs::exists(dir / (std::string(name) + ".svg"))) {
      made.push_back(dir / (std::string(name) + ".svg"));
    } else if (note->empty()) {
      *note = (why.empty() ? std::string("gnuplot wrote no figure") : why) + " (run gnuplot " + name +
              ".gp in this folder to retry)";
    }
  }
  return made;
}

}  // namespace

void write_record_folder(const fs::path& dir, const json& d, const RecordResiduals& r) {
  if (fs::exists(dir / "record.json")) {
    throw UsageError(dir.string() + " already holds a diagnosis (record.json): give another --out folder");
  }
  fs::create_directories(dir);
  engine::write_file_atomic((dir / "record.json").string(), d.dump(2) + "\n");
  std::string note;
  const std::vector<fs::path> figures = write_figures(dir, d, r, &note);
  engine::write_file_atomic((dir / "report.html").string(), engine::record_report_html(d, figures, note));
}

}  // namespace poise::cli
