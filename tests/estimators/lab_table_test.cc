// Tests of estimators/lab_table and oscillation_record: a lab's files as they come (delimiters,
// comments, headers with spaces and units, decimal commas, encoder counts, NumPy arrays, wrapped
// angles) and every error naming the file, the line and the column.
#include "estimators/lab_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <string>

#include "core/error.h"
#include "estimators/oscillation_record.h"
#include "estimators/torque_table.h"
#include "test_util.h"

namespace poise::estimators {
namespace {

constexpr double kPi = std::numbers::pi;

const std::vector<ColumnRole>& roles() { return record_column_roles(); }

ColumnMapping mapping(std::initializer_list<std::pair<std::string, std::string>> columns,
                      std::initializer_list<std::pair<std::string, std::string>> units) {
  ColumnMapping m;
  for (const auto& [role, header] : columns) add_column_option(m, "--column", role + "=" + header, roles());
  for (const auto& [role, unit] : units) add_column_option(m, "--unit", role + "=" + unit, roles());
  return m;
}

std::string error_of(const std::string& path, const ColumnMapping& m) {
  try {
    read_lab_table(path, roles(), m);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(LabTable, ReadsALoggersSemicolonFileWithCommentsDecimalCommasAndUnitsInHeaders) {
  test::TempDir d;
  const std::string path = d.file("log.csv");
  test::write_text(path,
                   "# logger v2, axis 1\n"
                   "% exported 2026-11-28\n"
                   "\n"
                   " t [ms] ; Iq (mA) ; pos\n"
                   "0;100,5;0\n"
                   "// a comment between rows\n"
                   "2,5;-200;16384\n");
  const LabTable t = read_lab_table(path, roles(),
                                    mapping({{"time", "t [ms]"}, {"current", "Iq (mA)"}, {"angle", "pos"}},
                                            {{"angle", "1/16384 rev"}}));
  EXPECT_EQ(t.delimiter, "semicolon");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.lines[0], 5u);
  EXPECT_EQ(t.lines[1], 7u);
  EXPECT_DOUBLE_EQ(t.at("time")[1], 2.5e-3);
  EXPECT_DOUBLE_EQ(t.at("current")[0], 0.1005);
  EXPECT_DOUBLE_EQ(t.at("current")[1], -0.2);
  EXPECT_NEAR(t.at("angle")[1], 2 * kPi, 1e-12);
  EXPECT_EQ(t.unit.at("time"), "ms");
}

TEST(LabTable, ReadsTabAndWhitespaceDelimitedFilesAndUnitSuffixes) {
  test::TempDir d;
  test::write_text(d.file("tab.txt"), "time_s\tcurrent_A\tposition_rad\n0\t1\t3.14\n");
  LabTable t = read_lab_table(d.file("tab.txt"), roles(), mapping({{"angle", "position_rad"}}, {}));
  EXPECT_EQ(t.delimiter, "tab");
  EXPECT_DOUBLE_EQ(t.at("angle")[0], 3.14);  // rad, from the header's suffix
  test::write_text(d.file("ws.txt"), "time_s   current_A  phi_deg\n  0   1   90  \n0.1 2 180\n");
  t = read_lab_table(d.file("ws.txt"), roles(), {});
  EXPECT_EQ(t.delimiter, "whitespace");
  EXPECT_NEAR(t.at("angle")[1], kPi, 1e-15);
}

TEST(LabTable, ErrorsNameTheFileLineColumnAndWhatWasExpected) {
  test::TempDir d;
  const std::string path = d.file("r.csv");
  test::write_text(path, "time,Iq,pos\n0,1,2\n0.1,x7,3\n");
  const ColumnMapping named = mapping({{"time", "time"}, {"current", "Iq"}, {"angle", "pos"}},
                                      {{"time", "s"}, {"current", "A"}, {"angle", "deg"}});
  EXPECT_NE(error_of(path, named).find(path + ":3:2: key 'column Iq' = x7: expected a finite number (the drive current)"),
            std::string::npos)
      << error_of(path, named);
  // A renamed column without a unit: the option that gives it.
  const ColumnMapping no_unit = mapping({{"time", "time"}, {"current", "Iq"}, {"angle", "pos"}}, {{"time", "s"}});
  EXPECT_NE(error_of(path, no_unit).find("key 'unit of column 'Iq' (drive current)' = (not given): expected --unit "
                                         "current=UNIT"),
            std::string::npos)
      << error_of(path, no_unit);
  // A unit of another kind.
  const ColumnMapping wrong = mapping({{"time", "time"}, {"current", "Iq"}, {"angle", "pos"}},
                                      {{"time", "mm"}, {"current", "A"}, {"angle", "deg"}});
  EXPECT_NE(error_of(path, wrong).find("= mm: expected a unit of a time"), std::string::npos) << error_of(path, wrong);
  // A header the file lacks: the headers it has.
  const ColumnMapping absent = mapping({{"current", "I_q"}}, {});
  EXPECT_NE(error_of(path, absent).find("key '--column current' = I_q: expected one of the file's headers: 'time', "
                                        "'Iq', 'pos'"),
            std::string::npos)
      << error_of(path, absent);
  // A role that does not exist, and a malformed option.
  ColumnMapping m;
  EXPECT_THROW(add_column_option(m, "--column", "voltage=U", roles()), InputError);
  EXPECT_THROW(add_column_option(m, "--unit", "angle", roles()), InputError);
}

TEST(LabTable, ReadsQuotedCellsAndDateTimeStamps) {
  // A spreadsheet's export: quoted headers holding the delimiter, time as dates and times.
  test::TempDir d;
  test::write_text(d.file("pc.csv"),
                   "\"Time\",\"Iq, A\",\"Position \"\"enc\"\"\"\n"
                   "2024-07-04 11:34:18.818,1.5,0\n"
                   "2024-07-04T11:34:19.318Z,\"2.5\",4096\n"
                   "2024-07-04T13:34:19.818+02:00,3,8192\n");
  const LabTable t = read_lab_table(
      d.file("pc.csv"), roles(),
      mapping({{"time", "Time"}, {"current", "Iq, A"}, {"angle", "Position \"enc\""}},
              {{"time", "s"}, {"current", "A"}, {"angle", "1/8192 rev"}}));
  ASSERT_EQ(t.size(), 3u);
  EXPECT_NEAR(t.at("time")[1] - t.at("time")[0], 0.5, 1e-6);
  EXPECT_NEAR(t.at("time")[2] - t.at("time")[0], 1.0, 1e-6);  // the offset taken off
  EXPECT_NEAR(t.at("time")[0], 1720092858.818, 1e-3);          // seconds since 1970 UTC
  EXPECT_DOUBLE_EQ(t.at("current")[1], 2.5);
  EXPECT_NEAR(t.at("angle")[2], 2 * kPi, 1e-12);
  // A stamp that is neither a number nor a date and time says what was expected.
  test::write_text(d.file("bad.csv"), "time_s,current_A,phi_deg\n2024-13-04 10:00:00,1,2\n");
  EXPECT_NE(error_of(d.file("bad.csv"), {}).find("expected a finite number, or a date and time"), std::string::npos)
      << error_of(d.file("bad.csv"), {});
}

TEST(LabTable, EveryMissingColumnIsNamedInOneMessage) {
  test::TempDir d;
  test::write_text(d.file("t.csv"), "a;b\n1;2\n");
  try {
    read_lab_table(d.file("t.csv"), torque_table_roles(), {});
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(d.file("t.csv") +
                                         ":1: missing columns 'theta_deg' (the turntable angle) and 'torque_mNm' (the "
                                         "unbalance torque): the file's columns are 'a', 'b'; name the ones that hold "
                                         "them with --column angle=HEADER --column torque=HEADER"),
              std::string::npos)
        << e.what();
  }
}

TEST(LabTable, UnitsOfColumnsIncludeCountsAsFractionsOfATurn) {
  EXPECT_NEAR(column_unit_factor("1/4096 rev", units::kAngle), 2 * kPi / 4096, 1e-15);
  EXPECT_NEAR(column_unit_factor("0.5 deg", units::kAngle), 0.5 * kPi / 180, 1e-15);
  EXPECT_DOUBLE_EQ(column_unit_factor("ns", units::kTime), 1e-9);
  EXPECT_THROW(column_unit_factor("0 deg", units::kAngle), Error);
  EXPECT_THROW(column_unit_factor("furlong", units::kAngle), Error);
}

void write_npy(const std::string& path, int rows, int cols, const std::vector<double>& values) {
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", " +
                       std::to_string(cols) + "), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream out(path, std::ios::binary);
  out.write("\x93NUMPY\x01\x00", 8);
  const auto len = static_cast<std::uint16_t>(header.size());
  out.put(static_cast<char>(len & 0xff)).put(static_cast<char>(len >> 8));
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size() * sizeof(double)));
}

TEST(LabTable, ReadsNumPyArraysWhoseRowsAreTheSeries) {
  test::TempDir d;
  // np.save of [t, counts, iq]: shape (3, 4), three series of four values.
  write_npy(d.file("lap.npy"), 3, 4, {0, 0.1, 0.2, 0.3, 0, 1024, 2048, 3072, 1, 2, 3, 4});
  const LabTable t = read_lab_table(d.file("lap.npy"), roles(),
                                    mapping({{"time", "0"}, {"angle", "1"}, {"current", "2"}},
                                            {{"time", "s"}, {"angle", "1/4096 rev"}, {"current", "A"}}));
  ASSERT_EQ(t.size(), 4u);
  EXPECT_NEAR(t.at("angle")[2], kPi, 1e-15);
  EXPECT_DOUBLE_EQ(t.at("current")[3], 4.0);
  EXPECT_EQ(t.delimiter, "NumPy .npy");
}

TEST(OscillationRecord, UnwrapsASingleTurnEncoderAndReadsATorqueColumn) {
  test::TempDir d;
  std::string text = "time_s,torque_Nm,phi_deg\n";
  for (int k = 0; k < 20; ++k) text += std::to_string(0.01 * k) + ",0.5," + std::to_string((k * 40) % 360) + "\n";
  test::write_text(d.file("wrap.csv"), text);
  const OscillationRecord r = read_oscillation_record(d.file("wrap.csv"));
  ASSERT_EQ(r.phi.size(), 20u);
  EXPECT_NEAR(r.phi[19], 19 * 40 * kPi / 180, 1e-12);  // 760 deg: unwrapped twice
  EXPECT_TRUE(r.current.empty());
  EXPECT_DOUBLE_EQ(r.torque[0], 0.5);
  bool said = false;
  for (const auto& n : r.notes) said = said || n.find("wraps 2 time(s)") != std::string::npos;
  EXPECT_TRUE(said);
}

TEST(OscillationRecord, AFileWithoutTimeIsAMapInRowOrder) {
  test::TempDir d;
  test::write_text(d.file("map.csv"), "count,Iq_A\n0,1\n16,2\n32,3\n");
  const OscillationRecord r =
      read_oscillation_record(d.file("map.csv"), mapping({{"angle", "count"}, {"current", "Iq_A"}},
                                                         {{"angle", "1/8192 rev"}}));
  EXPECT_TRUE(r.no_time);
  EXPECT_EQ(r.t, (std::vector<double>{0, 1, 2}));
  EXPECT_DOUBLE_EQ(r.current[2], 3.0);
}

}  // namespace
}  // namespace poise::estimators
