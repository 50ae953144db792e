// samples.h5 of a LOS run end to end through `poise run`: the grid values of every sample,
// one row per sample, the same data for any thread count; samples.csv keeps the inputs and
// scalar outputs; the pooled field figures of summary.json are those of the file's values.
// samples.h5 of the other kinds: the inputs and outputs as columns, each input with the unit
// its kind declares (never read off its name).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <nlohmann/json.hpp>

#include "core/units.h"
#include "h5_util.h"
#include "sampling/statistics.h"
#include "test_util.h"

namespace poise {
namespace {
using nlohmann::json;
using test::read_text;
using test::TempDir;

std::string los_study(const TempDir& d) {
  std::string text = read_text(test::source_path("studies/los_seeker_wang2011.toml"));
  text = test::replace_once(text, "model = \"../models/", "model = \"" + test::source_path("models") + "/");
  const auto sweep = text.find("[[sweep]]");
  if (sweep != std::string::npos) text.resize(sweep);
  text += "\n[output]\ncontribution_samples = 0\nplots = false\n";
  test::write_text(d.file("los.toml"), text);
  return d.file("los.toml");
}

TEST(SamplesH5, GridValuesOfEverySampleTheSameForAnyThreadCount) {
  TempDir d;
  const std::string study = los_study(d);
  setenv("POISE_INJECT_FAILURE_EVERY", "100", 1);
  const std::string args = "run '" + study + "' --samples 3000 --seed 5 -q --no-plots --out ";
  auto r1 = test::run_poise(d, args + "'" + d.file("t1") + "' --threads 1");
  auto r2 = test::run_poise(d, args + "'" + d.file("t2") + "' --threads 2");
  unsetenv("POISE_INJECT_FAILURE_EVERY");
  ASSERT_EQ(r1.status, 0) << r1.err;
  ASSERT_EQ(r2.status, 0) << r2.err;
  const auto a = test::read_h5_floats(d.file("t1/samples.h5"), "grid_total_arcsec");
  const auto b = test::read_h5_floats(d.file("t2/samples.h5"), "grid_total_arcsec");
  ASSERT_EQ(a.dims, (std::vector<std::size_t>{3000, 169}));
  EXPECT_TRUE(test::same_h5_floats(a, b));
  const json s1 = json::parse(read_text(d.file("t1/summary.json")));
  const json s2 = json::parse(read_text(d.file("t2/summary.json")));
  EXPECT_EQ(s1["samples_h5"]["values_digest"], s2["samples_h5"]["values_digest"]);
  EXPECT_EQ(s1["samples_h5"]["rows"], 3000);
  EXPECT_EQ(s1["samples_h5"]["unit"], "arcsec");

  // Failed samples (every 100th) are rows of NaN; the others are finite and non-negative.
  for (std::size_t i = 0; i < 3000; ++i) {
    const float v = a.values[i * 169 + 84];
    if ((i + 1) % 100 == 0) {
      EXPECT_TRUE(std::isnan(v)) << i;
    } else {
      ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << i;
    }
  }
  // Columns are grid points: their yaw and pitch over the field of regard, in degrees.
  const auto yaw = test::read_h5_floats(d.file("t1/samples.h5"), "grid_yaw_deg");
  const auto pitch = test::read_h5_floats(d.file("t1/samples.h5"), "grid_pitch_deg");
  ASSERT_EQ(yaw.values.size(), 169u);
  EXPECT_EQ(yaw.values.front(), -30.0f);
  EXPECT_EQ(yaw.values.back(), 30.0f);
  EXPECT_EQ(pitch.values[1] - pitch.values[0], 5.0f);

  // The greatest value of a row is that sample's los_max_arcsec output (samples.csv).
  const std::string csv = read_text(d.file("t1/samples.csv"));
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header.find("grid"), std::string::npos) << "grid values belong in samples.h5";
  const auto row7 = csv.find("\n7,ok,");
  ASSERT_NE(row7, std::string::npos);
  std::vector<std::string> cells;
  std::string line = csv.substr(row7 + 1, csv.find('\n', row7 + 1) - row7 - 1), cell;
  std::stringstream ss(line);
  while (std::getline(ss, cell, ',')) cells.push_back(cell);
  std::vector<std::string> names;
  std::stringstream hs(header);
  while (std::getline(hs, cell, ',')) names.push_back(cell);
  const auto col = static_cast<std::size_t>(std::find(names.begin(), names.end(), "los_max_arcsec") - names.begin());
  ASSERT_LT(col, cells.size());
  float row_max = 0.0f;
  for (std::size_t p = 0; p < 169; ++p) row_max = std::max(row_max, a.values[7 * 169 + p]);
  EXPECT_NEAR(row_max, std::stod(cells[col]), 1e-5 * std::stod(cells[col]));

  // The pooled field figures are the statistics of every value in the file.
  std::vector<double> all;
  for (float v : a.values) {
    if (!std::isnan(v)) all.push_back(v);
  }
  const sampling::Summary want = sampling::summarize(all);
  const json& pooled = s1["details"]["pooled_field_arcsec"];
  EXPECT_EQ(pooled["n"].get<std::size_t>(), want.n);
  EXPECT_EQ(pooled["p95"]["value"].get<double>(), want.p95.value);
  EXPECT_EQ(pooled["p99_73"]["ci95"][0].get<double>(), *want.p99_73.lo);
  EXPECT_EQ(pooled["max"]["value"].get<double>(), want.max.value);
  EXPECT_NEAR(pooled["mean"]["value"].get<double>(), want.mean.value, 1e-12 * want.mean.value);
  EXPECT_NEAR(pooled["std"]["value"].get<double>(), want.std.value, 1e-10 * want.std.value);
}

// What results/README.md shows a Python user: h5py reads the file, and the digest of
// summary.json is recomputed from the values with zlib and hashlib (python3-h5py, scripts/install_deps.sh).
TEST(SamplesH5, H5pyReadsTheFileAsTheReadmeShows) {
  if (std::system("/usr/bin/python3 -c 'import h5py, numpy' >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3-h5py is not installed (scripts/install_deps.sh installs it)";
  }
  TempDir d;
  auto r = test::run_poise(d, "run '" + los_study(d) + "' --samples 700 --seed 3 -q --no-plots --out '" + d.file("r") + "'");
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(read_text(d.file("r/summary.json")));
  test::write_text(d.file("check.py"), R"(import h5py, numpy as np, hashlib, sys, zlib
with h5py.File(sys.argv[1], "r") as f:
    grid = f["grid_total_arcsec"]
    a = grid[:, :]
    digest = hashlib.sha1(b"".join(zlib.crc32(a[:, p].astype("<f4").tobytes()).to_bytes(4, "big")
                                   for p in range(a.shape[1]))).hexdigest()
    yaw, pitch = f["grid_yaw_deg"][:], f["grid_pitch_deg"][:]
    corner = np.argmax(np.isclose(yaw, 30) & np.isclose(pitch, 30))
    print(grid.attrs["units"], a.shape[0], a.shape[1], digest, repr(float(np.nanpercentile(a, 95, method="median_unbiased"))), corner,
          int(f["sample"][-1]), int(f["ok"][:].sum()))
)");
  const std::string cmd = "/usr/bin/python3 '" + d.file("check.py") + "' '" + d.file("r/samples.h5") + "' >'" +
                          d.file("py.txt") + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << read_text(d.file("py.txt"));
  std::istringstream out(read_text(d.file("py.txt")));
  std::string unit, digest;
  std::size_t rows = 0, columns = 0, corner = 0, last = 0, ok = 0;
  double p95 = 0.0;
  out >> unit >> rows >> columns >> digest >> p95 >> corner >> last >> ok;
  EXPECT_EQ(unit, "arcsec");
  EXPECT_EQ(rows, 700u);
  EXPECT_EQ(columns, 169u);
  EXPECT_EQ(digest, s["samples_h5"]["values_digest"].get<std::string>());
  // numpy's median_unbiased is definition 8; the interpolation rounds differently in the last bits.
  EXPECT_NEAR(p95, s["details"]["pooled_field_arcsec"]["p95"]["value"].get<double>(), 1e-12 * std::abs(p95));
  EXPECT_EQ(corner, 168u);  // the last column: yaw +30, pitch +30
  EXPECT_EQ(last, 699u);
  EXPECT_EQ(ok, 700u);
}


// [output] keys leave out what a run does not need (issue 34): samples.csv, the grid values in
// samples.h5, the maps; what stays is the same as in the full run (same seed).
TEST(SamplesH5, OutputKeysLeaveOutFilesAndKeepTheAnswer) {
  TempDir d;
  const std::string study = los_study(d);
  std::string lean = read_text(study);
  lean = test::replace_once(lean, "contribution_samples = 0\n",
                            "contribution_samples = 0\nsamples_csv = false\ngrid_values = false\nmaps = false\n");
  test::write_text(d.file("lean.toml"), lean);
  std::string values_only = test::replace_once(lean, "maps = false", "maps = true");
  test::write_text(d.file("maps.toml"), values_only);
  const std::string args = " --samples 2000 --seed 9 -q --no-plots --threads 2 --out ";
  auto full = test::run_poise(d, "run '" + study + "'" + args + "'" + d.file("full") + "'");
  auto bare = test::run_poise(d, "run '" + d.file("lean.toml") + "'" + args + "'" + d.file("lean") + "'");
  auto maps = test::run_poise(d, "run '" + d.file("maps.toml") + "'" + args + "'" + d.file("maps") + "'");
  ASSERT_EQ(full.status, bare.status) << bare.err;
  ASSERT_EQ(full.status, maps.status) << maps.err;
  namespace fs = std::filesystem;
  EXPECT_TRUE(fs::exists(d.file("full/samples.csv")));
  EXPECT_TRUE(fs::exists(d.file("full/samples.h5")));
  for (const char* dir : {"lean", "maps"}) {
    EXPECT_FALSE(fs::exists(d.file(std::string(dir) + "/samples.csv"))) << dir;
    EXPECT_FALSE(fs::exists(d.file(std::string(dir) + "/samples.h5"))) << dir;
    EXPECT_TRUE(fs::exists(d.file(std::string(dir) + "/report.html"))) << dir;
  }
  const json a = json::parse(read_text(d.file("full/summary.json")));
  const json b = json::parse(read_text(d.file("lean/summary.json")));
  const json c = json::parse(read_text(d.file("maps/summary.json")));
  EXPECT_EQ(a["answer"], b["answer"]);
  EXPECT_EQ(a["outputs"], b["outputs"]);
  EXPECT_TRUE(b["samples_h5"].is_null());
  EXPECT_FALSE(b["details"].contains("pooled_field_arcsec"));
  // Maps without the grid values on disk: the same pooled figures, from memory.
  EXPECT_EQ(a["details"]["pooled_field_arcsec"], c["details"]["pooled_field_arcsec"]);
  // Without samples.csv there is nothing to resume from: a clear refusal, nothing changed.
  auto resume = test::run_poise(d, "run --resume '" + d.file("lean") + "' -q");
  EXPECT_EQ(resume.status, 2) << resume.err;
  EXPECT_NE(resume.err.find("samples_csv = false"), std::string::npos) << resume.err;
}

TEST(SamplesH5, EachInputHasTheUnitItsKindDeclares) {
  // Units a name's tail cannot give: "residual_unbalance_g_mm" is in g*mm, "youngs_modulus" a
  // pure number; each kind declares them, summary.json and samples.h5 carry them.
  const std::map<std::string, std::map<std::string, std::string>> expected{
      {"gimbal_unbalance_mc", {{"residual_unbalance_g_mm", "g*mm"}, {"axis_tilt_arcmin", "arcmin"}}},
      {"wang2014_balancing_mc", {{"rotor_residual_1_g_mm", "g*mm"}, {"youngs_modulus", "1"}}},
      {"shaft_sag_example", {{"youngs_modulus_GPa", "GPa"}}},
      {"geometry_mass_properties", {}}};
  for (const auto& [study, units] : expected) {
    SCOPED_TRACE(study);
    TempDir d;
    const auto r = test::run_poise(d, "run '" + test::source_path("studies/" + study + ".toml") +
                                          "' --samples 2 --threads 1 -q --no-plots --out '" + d.file("run") + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    const json s = json::parse(read_text(d.file("run/summary.json")));
    const json& declared = s["sampling"]["input_units"];
    ASSERT_EQ(declared.size(), s["sampling"]["inputs"].size());
    for (const auto& [name, unit] : units) EXPECT_EQ(declared.value(name, ""), unit) << name;
    for (const auto& name : s["sampling"]["inputs"]) {
      const std::string unit = declared[name.get<std::string>()].get<std::string>();
      EXPECT_NO_THROW(units::parse_quantity("1 " + unit)) << name << ": " << unit;
      EXPECT_EQ(test::read_h5_text_attribute(d.file("run/samples.h5"), "inputs/" + name.get<std::string>(), "units"),
                unit)
          << name;
    }
  }
}

}  // namespace
}  // namespace poise
