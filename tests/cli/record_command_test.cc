// `poise simulate-record` and `poise diagnose-record` (cli/record_command.cc) end to end
// through the poise binary: the record written, read back and diagnosed, their options, the
// outputs, and every error path (refused input: exit 2 with the file, line and key; a write
// the system refuses: exit 1 with the file and the reason).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>

#include "estimators/oscillation_record.h"
#include "core/format.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using poise::test::RunResult;
using poise::test::TempDir;

const std::string kModel = poise::test::source_path("models/gimbal_simulator_yang2015.toml");

RunResult poise_run(const TempDir& d, const std::string& args) { return poise::test::run_poise(d, args); }

std::string shq(const std::string& s) { return "'" + s + "'"; }

// A record simulated once for the tests of this file (the default position, seed 1).
const std::string& simulated_record(const TempDir& d) {
  static std::string path;
  if (path.empty() || !fs::exists(path)) {
    path = d.file("rec.csv");
    const RunResult r = poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(path));
    EXPECT_EQ(r.status, 0) << r.err;
  }
  return path;
}

TEST(SimulateRecord, WritesTheRecordOfOnePositionWithItsTorques) {
  TempDir d;
  const std::string rec = d.file("rec.csv");
  const RunResult r = poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(rec) + " --theta '45 deg' --seed 3");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("of the position theta = 45 deg to " + rec), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Eq. 21 torque"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mN*m"), std::string::npos) << r.out;
  // The file reads back: uniform time, the three columns, as many rows as announced.
  const poise::estimators::OscillationRecord back = poise::estimators::read_oscillation_record(rec);
  ASSERT_GT(back.t.size(), 100u);
  EXPECT_NE(r.out.find("wrote " + std::to_string(back.t.size()) + " samples"), std::string::npos) << r.out;
  EXPECT_EQ(poise::test::read_text(rec).rfind("time_s,current_A,phi_deg\n", 0), 0u);
  const double dt = back.t[1] - back.t[0];
  EXPECT_GT(dt, 0.0);
  for (std::size_t k = 1; k < back.t.size(); ++k) EXPECT_NEAR(back.t[k] - back.t[k - 1], dt, 2e-6) << k;
  // The gimbal oscillates: the angle goes both ways.
  double lo = back.phi[0], hi = back.phi[0];
  for (double p : back.phi) lo = std::min(lo, p), hi = std::max(hi, p);
  EXPECT_GT(hi - lo, 1e-3);
  // The same seed gives the same file; another seed another one (noise).
  const RunResult again = poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(d.file("again.csv")) +
                                           " --theta '45 deg' --seed 3");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(poise::test::read_text(rec), poise::test::read_text(d.file("again.csv")));
  const RunResult other = poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(d.file("other.csv")) +
                                           " --theta '45 deg' --seed 4");
  ASSERT_EQ(other.status, 0) << other.err;
  EXPECT_NE(poise::test::read_text(rec), poise::test::read_text(d.file("other.csv")));
}

TEST(DiagnoseRecord, TorqueIsLinearInTheTorqueConstantAndMatchesTheSimulatedEq21) {
  TempDir d;
  const std::string rec = d.file("rec.csv");
  const RunResult sim = poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(rec));
  ASSERT_EQ(sim.status, 0) << sim.err;
  double eq21 = NAN;
  ASSERT_EQ(std::sscanf(sim.out.c_str() + sim.out.find("Eq. 21 torque"), "Eq. 21 torque %lf", &eq21), 1) << sim.out;
  // The model's nominal K_T is the simulated one: read it from the printed line.
  const auto kt_at = sim.out.find("K_T = ");
  ASSERT_NE(kt_at, std::string::npos) << sim.out;
  const std::string kt = sim.out.substr(kt_at + 6, sim.out.find('\n', kt_at) - kt_at - 6);
  RunResult r = poise_run(d, "diagnose-record " + shq(rec) + " --kt " + shq(kt) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_GT(j["n_samples"].get<std::size_t>(), 100u);
  // K_T mean(i) over the record against the procedure's own Eq. 21 integral of the same run.
  EXPECT_NEAR(j["torque_eq21_mNm"].get<double>(), eq21, 0.02 * std::abs(eq21) + 0.01) << r.out;
  EXPECT_NEAR(j["torque_before_mNm"]["value"].get<double>(), eq21, 0.05 * std::abs(eq21) + 0.05) << r.out;
  EXPECT_GT(j["torque_before_mNm"]["se"].get<double>(), 0.0);
  EXPECT_GE(j["rmse_before_mNm"].get<double>(), j["rmse_after_mNm"].get<double>());
  ASSERT_TRUE(j["base_model"].contains("J"));
  EXPECT_GT(j["base_model"]["J"]["value"].get<double>(), 0.0);
  // Every torque scales with K_T, exactly: twice the constant, twice the torque.
  double kt_value = 0.0;
  char unit[32] = {};
  ASSERT_EQ(std::sscanf(kt.c_str(), "%lf %31s", &kt_value, unit), 2) << kt;
  r = poise_run(d, "diagnose-record " + shq(rec) + " --kt '" + std::to_string(2 * kt_value) + " " + unit + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j2 = json::parse(r.out);
  EXPECT_NEAR(j2["torque_eq21_mNm"].get<double>(), 2 * j["torque_eq21_mNm"].get<double>(),
              1e-9 * std::abs(j["torque_eq21_mNm"].get<double>()));
  EXPECT_NEAR(j2["torque_before_mNm"]["value"].get<double>(), 2 * j["torque_before_mNm"]["value"].get<double>(),
              1e-6 * std::abs(j["torque_before_mNm"]["value"].get<double>()));
  // The text report says the same, with its units.
  r = poise_run(d, "diagnose-record " + shq(rec) + " --kt " + shq(kt));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("Time-series diagnosis of " + rec), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("K_T i = J phi'' + B phi' + C sign(phi')"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("torque residual RMS"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mN*m"), std::string::npos) << r.out;
}

TEST(DiagnoseRecord, ALoggersFileAsItComesGivesTheSameDiagnosis) {
  // The simulated record rewritten as a logger keeps it: a comment, semicolons, decimal commas,
  // time in ms, the current in mA under another name, the angle as counts of a 16384-count
  // encoder that wraps once a turn, a column the diagnosis does not need.
  TempDir d;
  const std::string rec = d.file("cog.csv");
  ASSERT_EQ(poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(rec) +
                             " --set rotor.cogging_torque='0.3 mN*m' --set rotor.cogging_order=180")
                .status,
            0);
  std::istringstream in(poise::test::read_text(rec));
  std::string line, logged = "# bench logger 2.1, axis 2\nt [ms];temperature;Iq (mA);pos\n";
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    double t = 0, i = 0, phi = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &i, &phi), 3);
    const double counts = std::fmod(phi / 360.0 * 16384.0 + 2 * 16384.0, 16384.0);
    std::string row = fmt::format("{:.6f};21,5;{:.9g};{:.9g}\n", t * 1e3, i * 1e3, counts);
    std::replace(row.begin(), row.end(), '.', ',');
    logged += row;
  }
  const std::string log = d.file("axis2.log");
  poise::test::write_text(log, logged);
  const RunResult a = poise_run(d, "diagnose-record " + shq(rec) + " --json");
  const RunResult b = poise_run(d, "diagnose-record " + shq(log) +
                                       " --column time='t [ms]' --column current='Iq (mA)' --column angle=pos"
                                       " --unit angle='1/16384 rev' --json");
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  const json ja = json::parse(a.out), jb = json::parse(b.out);
  EXPECT_EQ(ja["motion"]["kind"], "swing");
  EXPECT_EQ(jb["motion"]["kind"], "swing");
  ASSERT_FALSE(jb["effects"].empty());
  EXPECT_EQ(jb["effects"][0]["order"], ja["effects"][0]["order"]);
  const double amp_a = ja["effects"][0]["params"]["amplitude"]["value"], amp_b = jb["effects"][0]["params"]["amplitude"]["value"];
  EXPECT_NEAR(amp_b, amp_a, 1e-3 * amp_a);  // the file's rounding only
  EXPECT_NEAR(jb["torque_after_mNm"]["value"].get<double>(), ja["torque_after_mNm"]["value"].get<double>(), 1e-3);
  // What the reading did is said.
  const std::string reading = jb["reading"].dump();
  EXPECT_NE(reading.find("delimited by semicolon"), std::string::npos) << reading;
  EXPECT_NE(reading.find("current: column 'Iq (mA)' in mA"), std::string::npos) << reading;
}

TEST(DiagnoseRecord, TheCoggingFoundGoesBackIntoTheModelAsAMap) {
  // A cogging map in the model file ([[rotor.cogging]]) is the same torque as the single-order
  // keys: the simulated records are identical.
  TempDir d;
  const std::string base = poise::test::read_text(kModel);
  const std::string with_map = d.file("map.toml");
  poise::test::write_text(with_map, base + "\n[[rotor.cogging]]\norder = 180\ntorque = \"0.3 mN*m\"\n");
  ASSERT_EQ(poise_run(d, "simulate-record " + shq(with_map) + " --out " + shq(d.file("a.csv"))).status, 0);
  ASSERT_EQ(poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(d.file("b.csv")) +
                             " --set rotor.cogging_torque='0.3 mN*m' --set rotor.cogging_order=180")
                .status,
            0);
  EXPECT_EQ(poise::test::read_text(d.file("a.csv")), poise::test::read_text(d.file("b.csv")));
  // The diagnosis prints the map's lines; put into the model, they give back a record whose
  // diagnosis is the measured one's.
  RunResult r = poise_run(d, "diagnose-record " + shq(d.file("a.csv")));
  ASSERT_EQ(r.status, 0) << r.err;
  std::smatch m_line;
  ASSERT_TRUE(std::regex_search(r.out, m_line,
                                std::regex(R"re(\[\[rotor\.cogging\]\] order = (\d+), torque = "([^"]+)", phase = "([^"]+)")re")))
      << r.out;
  const std::string lines = "[[rotor.cogging]]\norder = " + m_line[1].str() + "\ntorque = \"" + m_line[2].str() +
                            "\"\nphase = \"" + m_line[3].str() + "\"\n";
  const std::string found_model = d.file("found.toml");
  poise::test::write_text(found_model, base + "\n" + lines + "\n");
  ASSERT_EQ(poise_run(d, "simulate-record " + shq(found_model) + " --out " + shq(d.file("c.csv"))).status, 0);
  const json measured = json::parse(poise_run(d, "diagnose-record " + shq(d.file("a.csv")) + " --json").out);
  const RunResult again = poise_run(d, "diagnose-record " + shq(d.file("c.csv")) + " --json");
  ASSERT_EQ(again.status, 0) << again.err << "\nmodel lines:\n" << lines;
  const json simulated = json::parse(again.out);
  ASSERT_FALSE(simulated["effects"].empty());
  const auto& m = measured["effects"][0];
  const auto& s = simulated["effects"][0];
  EXPECT_NEAR(s["order"].get<double>(), m["order"].get<double>(), m["order_resolution"].get<double>());
  const double se = m["params"]["amplitude"]["se"];
  EXPECT_NEAR(s["params"]["amplitude"]["value"].get<double>(), m["params"]["amplitude"]["value"].get<double>(),
              4 * se);
}

TEST(DiagnoseRecord, FindsTheCoggingTheSimulationWasGiven) {
  TempDir d;
  const std::string rec = d.file("cog.csv");
  const RunResult sim = poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(rec) +
                                         " --set rotor.cogging_torque='0.3 mN*m' --set rotor.cogging_order=180");
  ASSERT_EQ(sim.status, 0) << sim.err;
  const RunResult r = poise_run(d, "diagnose-record " + shq(rec) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  bool found = false;
  for (const auto& e : j["effects"]) {
    if (e["name"] != "cogging") continue;
    found = true;
    // A swing of 2.55 deg holds 1.3 cycles of order 180 (2 deg each): the order is resolved
    // only to several per turn (172-177 found over noise realisations): within 8% of the
    // simulated one; the amplitude within 5%.
    EXPECT_NEAR(e["order"].get<int>(), 180, 15) << e.dump();
    EXPECT_LT(e["p_adjusted"].get<double>(), 0.05);
    EXPECT_NEAR(e["params"]["amplitude"]["value"].get<double>(), 0.3e-3, 0.015e-3) << e.dump();
    EXPECT_EQ(e["params"]["amplitude"]["unit"], "N*m");
  }
  EXPECT_TRUE(found) << r.out;
  // The text report gives the --set lines that put the effect into the model.
  const RunResult t = poise_run(d, "diagnose-record " + shq(rec));
  ASSERT_EQ(t.status, 0) << t.err;
  EXPECT_NE(t.out.find("--set rotor.cogging_torque="), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("--set rotor.cogging_order="), std::string::npos) << t.out;
}

TEST(SimulateRecord, RefusedInputGivesExit2WithTheKeyOrOption) {
  TempDir d;
  const std::string out = " --out " + shq(d.file("x.csv"));
  RunResult r = poise_run(d, "simulate-record " + shq(kModel) + out + " --set rotor.cogging_order");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--set rotor.cogging_order: expected key=value"), std::string::npos) << r.err;
  r = poise_run(d, "simulate-record " + shq(kModel) + out + " --set rotor.no_such_key=1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("rotor.no_such_key"), std::string::npos) << r.err;
  r = poise_run(d, "simulate-record " + shq(kModel) + out + " --set rotor.cogging_order=-3");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("cogging_order"), std::string::npos) << r.err;
  r = poise_run(d, "simulate-record " + shq(kModel) + out + " --theta '30 mm'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--theta '30 mm': wrong unit"), std::string::npos) << r.err;
  r = poise_run(d, "simulate-record " + shq(kModel) + out + " --theta '1e308 deg'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--theta '1e308 deg': expected a turntable angle within +-3600 deg"), std::string::npos)
      << r.err;
  // A value the equations cannot integrate: the solver's failure, with the values set here.
  r = poise_run(d, "simulate-record " + shq(kModel) + out +
                       " --set 'rotor.cogging_torque=1e308 N*m' --set rotor.cogging_order=180");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("the simulation of the position theta = 30 deg failed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rotor.cogging_torque = 1e308 N*m"), std::string::npos) << r.err;
  r = poise_run(d, "simulate-record " + shq(d.file("missing.toml")) + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("missing.toml"), std::string::npos) << r.err;
  r = poise_run(d, "simulate-record " + shq(kModel));  // --out is required
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d.file("x.csv")));  // a refused command writes nothing
}

TEST(SimulateRecord, AFailedWriteGivesExit1WithTheFileAndTheReasonAndLeavesNoTemporary) {
  TempDir d;
  RunResult r = poise_run(d, "simulate-record " + shq(kModel) + " --out " + shq(d.file("no/such/dir/rec.csv")));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("no/such/dir/rec.csv"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("No such file or directory"), std::string::npos) << r.err;
  const std::string cmd = "POISE_INJECT_WRITE_FAILURE_AFTER=1000 POISE_INJECT_WRITE_FAILURE_FILE=disk.csv '" +
                          ::poise::test::poise_binary() + "' simulate-record " + shq(kModel) + " --out " +
                          shq(d.file("disk.csv")) + " >" + shq(d.file("o.txt")) + " 2>" + shq(d.file("e.txt"));
  const int raw = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 1);
  const std::string err = poise::test::read_text(d.file("e.txt"));
  EXPECT_NE(err.find(d.file("disk.csv") + ".tmp: No space left on device"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d.file("disk.csv.tmp")));
  EXPECT_FALSE(fs::exists(d.file("disk.csv")));  // never half a record
}

TEST(DiagnoseRecord, RefusedRecordsGiveExit2WithFileLineAndColumn) {
  TempDir d;
  const std::string good = poise::test::read_text(simulated_record(d));
  auto with = [&](const std::string& name, const std::string& text) {
    poise::test::write_text(d.file(name), text);
    return poise_run(d, "diagnose-record " + shq(d.file(name)));
  };
  // A missing column names the file, line 1 and the column.
  RunResult r = with("nocol.csv", "time_s,current_A\n0,1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(d.file("nocol.csv") +
                       ":1: missing column 'phi_deg' (the axis angle): the file's columns are 'time_s', 'current_A'; "
                       "name the one that holds it with --column angle=HEADER"),
            std::string::npos)
      << r.err;
  // A cell that is not a number: file, line, column, the cell.
  std::string bad = good;
  const auto line3 = bad.find('\n', bad.find('\n') + 1) + 1;  // start of line 3
  bad.replace(line3, bad.find(',', line3) - line3, "12abc");
  r = with("cell.csv", bad);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(d.file("cell.csv") + ":3:1: key 'column time_s' = 12abc: expected a finite number"),
            std::string::npos) << r.err;
  // A value past double's range, or not finite.
  r = with("inf.csv", "time_s,current_A,phi_deg\n0,1e999,0\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(":2:2: key 'column current_A' = 1e999"), std::string::npos) << r.err;
  r = with("nan.csv", "time_s,current_A,phi_deg\n0,1,nan\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(":2:3: key 'column phi_deg' = nan"), std::string::npos) << r.err;
  // A row with a cell too many.
  r = with("cells.csv", "time_s,current_A,phi_deg\n0,1,2\n0.001,1,2,3\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(d.file("cells.csv") + ":3: 4 cells, the header (line 1) has 3"), std::string::npos) << r.err;
  // A 3 MB cell is echoed cut, not whole.
  r = with("huge.csv", "time_s,current_A,phi_deg\n" + std::string(3'000'000, '7') + "x,1,2\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_LT(r.err.size(), 2000u);
  EXPECT_NE(r.err.find("(3000001 bytes)"), std::string::npos) << r.err.substr(0, 400);
  // Too short to diagnose.
  r = with("short.csv", "time_s,current_A,phi_deg\n0,1,2\n0.001,1,2\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(d.file("short.csv") + ": 2 samples; expected at least 72"), std::string::npos) << r.err;
  // A leading plus sign is a number; two are not.
  r = with("plus.csv", "time_s,current_A,phi_deg\n0,+1,++2\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(":2:3: key 'column phi_deg' = ++2"), std::string::npos) << r.err;
  // CRLF line ends and a byte order mark are accepted.
  std::string crlf = "\xEF\xBB\xBF";
  std::istringstream lines(good);
  for (std::string l; std::getline(lines, l);) crlf += l + "\r\n";
  r = with("crlf.csv", crlf);
  EXPECT_EQ(r.status, 0) << r.err;
  // A missing file: CLI11's check, exit 2.
  r = poise_run(d, "diagnose-record " + shq(d.file("none.csv")));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("none.csv"), std::string::npos) << r.err;
}

TEST(DiagnoseRecord, TorqueConstantsOutOfRangeAreRefusedWithTheValue) {
  TempDir d;
  const std::string rec = simulated_record(d);
  for (const char* kt : {"0 N*m/A", "-0.05 N*m/A", "1e308 N*m/A", "1e7 N*m/A", "nan N*m/A", "inf N*m/A"}) {
    const RunResult r = poise_run(d, "diagnose-record " + shq(rec) + " --kt '" + kt + "'");
    EXPECT_EQ(r.status, 2) << kt << ": " << r.err;
    EXPECT_TRUE(r.err.find(kt) != std::string::npos || r.err.find("expected a finite value in (0, 1e6) N*m/A") !=
                                                           std::string::npos) << kt << ": " << r.err;
    EXPECT_LT(r.err.size(), 400u) << r.err;  // the value in a few digits, not 309
  }
  const RunResult r = poise_run(d, "diagnose-record " + shq(rec) + " --kt '0.05 N*m'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--kt '0.05 N*m'"), std::string::npos) << r.err;
}

}  // namespace
