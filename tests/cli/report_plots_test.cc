// One run with plots per study kind (the other tests run with plots off): the smallest
// shipped study of each kind at a few samples, through the poise binary, must give a
// report.html with its figures inline (SVG from gnuplot, installed by
// scripts/install_deps.sh), a figure for every gnuplot script in plots/, and no note that a
// figure could not be made.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>

#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using poise::test::TempDir;

bool gnuplot_installed() { return std::system("gnuplot --version >/dev/null 2>&1") == 0; }

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// Runs the study with plots and checks the report; returns report.html.
std::string run_with_plots(const TempDir& d, const std::string& study, const std::string& extra,
                           std::size_t min_figures) {
  const auto r = poise::test::run_poise(d, "run '" + study + "' -q --threads 2 " + extra + " --out '" + d.file("run") + "'");
  EXPECT_EQ(r.status, 0) << r.err;
  const std::string html = poise::test::read_text(d.file("run/report.html"));
  EXPECT_GE(count_of(html, "<svg"), min_figures) << study;
  EXPECT_EQ(html.find("gnuplot could not be started"), std::string::npos) << study;
  EXPECT_EQ(html.find("gnuplot failed"), std::string::npos) << study;
  // Every script gave its figure, and every figure made is in the page.
  std::size_t scripts = 0;
  for (const auto& e : fs::directory_iterator(d.file("run/plots"))) {
    if (e.path().extension() != ".gp") continue;
    ++scripts;
    fs::path svg = e.path();
    svg.replace_extension(".svg");
    EXPECT_TRUE(fs::exists(svg)) << svg;
    if (fs::exists(svg)) {
      EXPECT_GT(fs::file_size(svg), 500u) << svg;
    }
  }
  EXPECT_GE(scripts, min_figures) << study;
  EXPECT_GE(count_of(html, "<svg"), scripts) << study << ": a figure is missing from report.html";
  return html;
}

class ReportPlots : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(gnuplot_installed()) << "gnuplot is not installed: scripts/install_deps.sh installs gnuplot-nox";
  }
};

TEST_F(ReportPlots, SeekerLos) {
  // The shipped study with its sweeps and contributions at a few samples each.
  TempDir d;
  std::string text = poise::test::read_text(poise::test::source_path("studies/los_seeker_wang2011.toml"));
  text = poise::test::replace_once(text, "model = \"../models/", "model = \"" + poise::test::source_path("models") + "/");
  text = std::regex_replace(text, std::regex("samples = 4096"), "samples = 16");
  text += "\n[output]\ncontribution_samples = 16\n";
  poise::test::write_text(d.file("seeker.toml"), text);
  const std::string html = run_with_plots(d, d.file("seeker.toml"), "--samples 16", 4);
  EXPECT_TRUE(fs::exists(d.file("run/plots/map_p95.svg")));  // the field map
  // Each sweep draws the statistic its requirement names against the value (the engine's
  // sweep figures, as for every kind).
  for (const char* sweep : {"sweep0_los_max_px_p99_73.svg", "sweep1_los_max_px_p99_73.svg", "sweep2_los_max_px_p99_73.svg"}) {
    EXPECT_TRUE(fs::exists(d.file("run/plots/") + sweep)) << sweep;
  }
  EXPECT_NE(html.find("yaw.bearing_span"), std::string::npos);
}

TEST_F(ReportPlots, GimbalStaticUnbalance) {
  TempDir d;
  run_with_plots(d, poise::test::source_path("studies/gimbal_unbalance_mc.toml"), "--samples 8", 2);
}

TEST_F(ReportPlots, BalancingMachine) {
  TempDir d;
  run_with_plots(d, poise::test::source_path("studies/wang2014_balancing_mc.toml"), "--samples 8", 2);
}

TEST_F(ReportPlots, PlatformBalancing) {
  TempDir d;
  run_with_plots(d, poise::test::source_path("studies/platform_balancing_sequence.toml"), "--samples 8", 2);
}

TEST_F(ReportPlots, GeometryMassProperties) {
  TempDir d;
  run_with_plots(d, poise::test::source_path("studies/geometry_mass_properties.toml"), "--samples 8", 2);
}

TEST_F(ReportPlots, LosObstruction) {
  TempDir d;
  run_with_plots(d, poise::test::source_path("studies/los_obstruction.toml"), "--samples 8", 2);
}

}  // namespace
