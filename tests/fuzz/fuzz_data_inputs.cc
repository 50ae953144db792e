// Input kinds of the fuzz target: measured data and meshes. See fuzz_inputs.cc for the
// selectors and what counts as a finding.
//   c  torque CSV: read_torque_table, fit_sine, diagnose_residuals (what `poise fit` and
//      `poise diagnose` do with the file)
//   r  raw record: the first line is the --kt value as typed (e.g. "1e308 N*m/A", which gave
//      an uncaught Boost.Math NaN error in issue 20), the rest the CSV; parsed and checked as
//      `poise diagnose-record` does, then read_oscillation_record and diagnose_oscillation
//   o/s  OBJ / STL: load_mesh (weld, needles, polygons), check_mesh (with the gaps' widths),
//      drop_duplicate_triangles, and for a valid mesh its exact moments and a ray cast with its
//      overlap (what a user part in a model goes through, engine/study_files/user_parts.cc)
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "core/units.h"
#include "estimators/oscillation_diagnosis.h"
#include "estimators/oscillation_record.h"
#include "estimators/record_map_diagnosis.h"
#include "estimators/record_motion.h"
#include "estimators/residual_diagnosis.h"
#include "estimators/sine_fit.h"
#include "estimators/torque_table.h"
#include "fuzz_common.h"
#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_needles.h"

namespace poise::fuzz {
namespace {

// A record of one position as the servo drives it, phidot = A sin(2 pi t / T), from the
// base model K_T i = J phi'' + B phi' + C sign(phi') + M_0 (+ cogging), with a little
// deterministic noise: a seed the diagnosis can fit.
std::string synthetic_record(int n, double cogging) {
  const double kPi = 3.14159265358979323846, dt = 0.005, T = 2.0, A = 0.4, kt = 0.05;
  const double J = 2e-3, B = 1e-3, C = 3e-4, M0 = 12.91e-3;
  std::uint32_t lcg = 12345;
  auto noise = [&] {
    lcg = lcg * 1664525u + 1013904223u;
    return (static_cast<double>(lcg >> 8) / 16777216.0 - 0.5) * 1e-5;
  };
  std::string out = "time_s,current_A,phi_deg\n";
  char buf[96];
  for (int k = 0; k < n; ++k) {
    const double t = k * dt, w = 2 * kPi / T;
    const double rate = A * std::sin(w * t), acc = A * w * std::cos(w * t);
    const double phi = 0.3 - A / w * std::cos(w * t);
    const double torque = J * acc + B * rate + C * (rate >= 0 ? 1.0 : -1.0) + M0 + cogging * std::sin(180 * phi);
    std::snprintf(buf, sizeof buf, "%.6f,%.9g,%.9g\n", t, torque / kt + noise(), phi / units::kRadPerDeg);
    out += buf;
  }
  return out;
}

std::string torque_table(bool time, bool sweep, bool se) {
  std::string out = std::string("theta_deg") + (time ? ",time_s" : "") + (sweep ? ",sweep" : "") + ",torque_mNm" +
                    (se ? ",torque_se_mNm" : "") + "\n";
  char buf[160];
  for (int k = 0; k < 36; ++k) {
    const double th = 10.0 * k, tq = 12.91 * std::sin((th + 45.5) * units::kRadPerDeg) + 0.3 * std::sin(2 * th * units::kRadPerDeg);
    std::string row = std::to_string(th);
    if (time) row += "," + std::to_string(60.0 * k);
    if (sweep) row += k % 2 ? ",-1" : ",1";
    std::snprintf(buf, sizeof buf, ",%.6f", tq);
    row += buf;
    if (se) row += ",0.05";
    out += row + "\n";
  }
  return out;
}

void add_folder(AddSeed add, char selector, const fs::path& dir, const std::string& ext) {
  if (!fs::is_directory(dir)) return;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().extension() != ext) continue;
    if (e.file_size() > 262144) continue;  // past the fuzzer's -max_len
    add(selector, read_file(e.path()));
  }
}

// Faulty exports of a closed part (issue 30), from a 10 mm box `m`: what real CAD files were
// found to hold. Each variant is a seed of the STL ('s') or OBJ ('o') reader.
void add_faulty_exports(AddSeed add, const geometry::Mesh& m) {
  const std::string ascii = geometry::ascii_stl_text(m, 1e-3);
  // Cracked: each facet's copies of a vertex a few float32 ulps apart.
  std::string cracked = "solid cracked\n";
  char buf[160];
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    cracked += " facet normal 0 0 0\n  outer loop\n";
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector3d p = m.vertices[m.triangles[k][e]] * (1e3 * (1.0 + 3e-8 * static_cast<double>(k % 5)));
      std::snprintf(buf, sizeof buf, "   vertex %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
      cracked += buf;
    }
    cracked += "  endloop\n endfacet\n";
  }
  add('s', cracked + "endsolid cracked\n");
  // Duplicated: every face listed twice.
  geometry::Mesh twice = m;
  for (std::size_t k = 0; k < m.triangles.size(); ++k) twice.triangles.push_back(m.triangles[k]);
  add('o', geometry::obj_text(twice, 1e-3));
  // Needles: two collinear triangles back to back on an edge, and one closing a T-junction.
  geometry::Mesh needles = m;
  const geometry::Triangle t = m.triangles[0];
  needles.vertices.push_back((m.vertices[t[0]] + m.vertices[t[1]]) / 2.0);
  const auto mid = static_cast<std::uint32_t>(needles.vertices.size() - 1);
  geometry::Mesh tjunction = needles;
  needles.triangles.push_back({t[0], t[1], mid});
  needles.triangles.push_back({t[0], mid, t[1]});
  add('s', geometry::ascii_stl_text(needles, 1e-3));
  tjunction.triangles[0] = {t[0], mid, t[2]};
  tjunction.triangles.push_back({mid, t[1], t[2]});
  tjunction.triangles.push_back({t[0], t[1], mid});
  add('s', geometry::stl_bytes(tjunction, 1e-3));
  // A byte-order mark before ASCII STL and OBJ; capital keywords and '+' signs.
  add('s', "\xEF\xBB\xBF" + ascii);
  add('o', "\xEF\xBB\xBF" + geometry::obj_text(m, 1e-3));
  std::string upper = ascii;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  add('s', upper);
  std::string plus = ascii;  // "vertex +10 +0 ..." where the first number is not negative
  for (std::size_t at = plus.find("vertex "); at != std::string::npos; at = plus.find("vertex ", at + 1)) {
    if (plus[at + 7] != '-') plus.insert(at + 7, "+");
  }
  add('s', plus);
  // Polygons: a cube whose bottom edge carries a vertex shared by two pentagons (a fan from
  // their first vertex would be a sliver), and an L-shaped prism (concave faces).
  add('o', "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\nv 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\nv 5 0 0\n"
           "f 1 4 3 2 9\nf 1 9 2 6 5\nf 5 6 7 8\nf 2 3 7 6\nf 3 4 8 7\nf 1 5 8 4\n");
  add('o', "v 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nv 0 0 0\nv 2 0 0\nv 2 1 3\nv 1 1 3\nv 1 2 3\nv 0 2 3\n"
           "v 0 0 3\nv 2 0 3\nf 6 5 4 3 2 1\nf 7 8 9 10 11 12\nf 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\n"
           "f 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n");
  // Shells overlapping by a trace, as touching curved faces do.
  geometry::Mesh slabs = geometry::box({0, 0, 0}, {0.02, 0.02, 0.005}, 1, "slabs");
  slabs.append(geometry::box({0, 0, 0.005 - 2e-9}, {0.02, 0.02, 0.01}, 1, ""));
  add('o', geometry::obj_text(slabs, 1e-3));
}

}  // namespace

void seed_data_inputs(AddSeed add) {
  add_folder(add, 'c', kSource / "data", ".csv");
  add('c', torque_table(false, false, false));
  add('c', torque_table(true, true, true));
  add('c', "\xEF\xBB\xBFtheta_deg,torque_Nm\r\n0,1e308\r\n90,-1e308\r\n180,1e308\r\n270,-1e308\r\n");
  add('c', "theta_deg,torque_mNm\n0,1\n0,1\n360,1\n720,1\n");
  // Found here: 1e308 mN*m among ordinary torques gave a NaN chi-square in the diagnosis.
  add('c', "theta_deg,torque_mNm\n0,9.208063\n10,10.742075\n20.0004,11.940436\n30,10.1\n180,-9.20308\r\n"
           "180,1e308\r\n200,-3.492213\n310,-1.308349\n320,0.941926\n330,3.19024\n340,5.365062\n350,7.394269\n");
  // --kt values: the default, the overflow, the edges of double, other units.
  const std::string record = synthetic_record(800, 0.0);
  for (const char* kt : {"0.05 N*m/A", "1e308 N*m/A", "1e-308 N*m/A", "0 N*m/A", "-0.05 N*m/A", "50 mN*m/A",
                         "nan N*m/A", "1e308 mN*m/A"}) {
    add('r', std::string(kt) + "\n" + record);
  }
  add('r', "0.05 N*m/A\n" + synthetic_record(800, 0.3e-3));
  add('r', "0.05 N*m/A\n" + synthetic_record(40, 0.0));
  add('r', "0.05 N*m/A\ntime_s,current_A,phi_deg\n0,1e308,0\n0.005,-1e308,1e308\n");
  // Meshes: the tests' and the worked example's, and closed solids written here.
  add_folder(add, 'o', kSource / "tests/data/meshes", ".obj");
  add_folder(add, 's', kSource / "tests/data/meshes", ".stl");
  add_folder(add, 'o', kSource / "examples/user_parts/meshes", ".obj");
  add_folder(add, 's', kSource / "examples/user_parts/meshes", ".stl");
  const geometry::Mesh tube = geometry::tube(0.01, 0.04, 0.0, 0.005, 24, "disk");
  const geometry::Mesh box = geometry::box({0, 0, 0}, {0.01, 0.02, 0.03}, 1, "box");
  for (const geometry::Mesh* m : {&tube, &box}) {
    add('o', geometry::obj_text(*m, 1e-3));
    add('s', geometry::stl_bytes(*m, 1e-3));
    add('s', geometry::ascii_stl_text(*m, 1e-3));
  }
  add_faulty_exports(add, box);
}

void fuzz_torque_csv(std::string_view text) {
  const fs::path file = work_dir() / "fuzz_table.csv";
  write_file(file, text);
  const estimators::TorqueTable t = estimators::read_torque_table(file.string());
  (void)estimators::fit_sine(t.theta_rad, t.torque);
  (void)estimators::diagnose_residuals(t, {});
}

void fuzz_record(std::string_view text) {
  const auto eol = text.find('\n');
  const std::string kt_text(text.substr(0, eol));
  const std::string_view csv = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
  estimators::OscillationOptions opt;
  opt.kt = units::parse_as(kt_text, units::Dimension{{2, 1, -2, -1, 0, 0}});  // as record_command.cc
  const fs::path file = work_dir() / "fuzz_record.csv";
  write_file(file, csv);
  const estimators::OscillationRecord r = estimators::read_oscillation_record(file.string());
  // As `poise diagnose-record` does: the motion first, then the diagnosis that reads it.
  if (estimators::record_motion(r, opt).kind == "swing") {
    (void)estimators::diagnose_oscillation(r, opt);
  } else {
    (void)estimators::diagnose_map(r, opt);
  }
}

void fuzz_mesh(std::string_view text, const char* extension) {
  const fs::path file = work_dir() / (std::string("fuzz_part") + extension);
  write_file(file, text);
  geometry::Mesh m = geometry::load_mesh(file.string(), 1e-3);
  (void)geometry::unneeded_needles(m);
  (void)geometry::check_mesh(m);
  (void)geometry::drop_duplicate_triangles(m);
  (void)geometry::check_mesh(m);
  (void)geometry::require_valid_mesh(m);
  (void)geometry::unit_warning(m, "mm", 1e-3);
  (void)geometry::to_mass_properties(geometry::exact_moments(m, 1000.0));
  geometry::RayGridOptions grid;
  grid.rays_per_side = 24;
  m.bounds().sizes().minCoeff(&grid.axis);
  geometry::RayCastStats stats;
  (void)geometry::raycast_moments({{m, 1.0}}, grid, &stats);
}

}  // namespace poise::fuzz
