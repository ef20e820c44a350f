// Real logs into series (docs/identifier.md §7.1): bridging, resampling, segments, and the
// regressor never reaching across a break.
#include "sysid/model/series_from_table.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sysid/model/free_run.hpp"
#include "sysid/model/nothing_to_identify.hpp"

namespace odonata::sysid {
namespace {

SeriesOptions Options(const std::string& time = "", int max_gap = 2) {
  SeriesOptions o;
  o.outputs = {"y"};
  o.inputs = {"u"};
  o.time_column = time;
  o.max_gap = max_gap;
  o.min_segment = 2;
  return o;
}

TEST(SeriesFromTable, BridgesShortRunsLinearlyAndCutsLongOnes) {
  const auto table =
      io::CsvTable::Parse("u,y\n0,0\n1,\n2,nan\n3,3\n4,4\nnan,5\nnan,6\nnan,7\n8,8\n9,9\n10,10\n",
                          "t.csv", io::MissingCells::kKeepAsNaN);
  SeriesReport r;
  const Series s = SeriesFromTable(table, Options(), &r);
  // Rows 1-2 of y bridged (run of 2); rows 5-7 of u (run of 3 > 2) cut.
  EXPECT_EQ(r.bridged, 2);
  EXPECT_EQ(r.missing, 3);
  EXPECT_EQ(r.segments, 2);
  ASSERT_EQ(s.samples(), 8);
  EXPECT_EQ(s.breaks, (std::vector<Eigen::Index>{5}));
  EXPECT_DOUBLE_EQ(s.outputs(1, 0), 1.0);
  EXPECT_DOUBLE_EQ(s.outputs(2, 0), 2.0);
  EXPECT_DOUBLE_EQ(s.outputs(5, 0), 8.0);  // the second segment starts at row 8
}

TEST(SeriesFromTable, ResamplesATimeColumnOntoTheRateAndCutsAtLongTimeGaps) {
  // 10 Hz with jitter, then a 1 s hole; y = 10 t throughout.
  const auto table = io::CsvTable::Parse(
      "t,u,y\n0.0,0,0\n0.11,1,1.1\n0.2,2,2\n0.3,3,3\n1.3,4,13\n1.4,5,14\n1.5,6,15\n", "t.csv",
      io::MissingCells::kKeepAsNaN);
  SeriesReport r;
  SeriesOptions o = Options("t");
  o.rate_hz = 10;
  const Series s = SeriesFromTable(table, o, &r);
  EXPECT_EQ(r.segments, 2);
  ASSERT_EQ(s.samples(), 7);  // 0.0-0.3 and 1.3-1.5: the resampled y is 10 × the grid time
  for (Eigen::Index k = 0; k < 4; ++k) EXPECT_NEAR(s.outputs(k, 0), double(k), 1e-9);
  for (Eigen::Index k = 4; k < 7; ++k) EXPECT_NEAR(s.outputs(k, 0), double(k + 9), 1e-9);
  EXPECT_EQ(s.breaks, (std::vector<Eigen::Index>{4}));
  EXPECT_EQ(r.missing, 9);
  // Without a rate, the median step (0.1 s here).
  SeriesFromTable(table, Options("t"), &r);
  EXPECT_NEAR(r.rate_hz, 10.0, 1e-6);
}

TEST(SeriesFromTable, NothingUsableIsAClearError) {
  const auto table = io::CsvTable::Parse("u,y\n0,nan\n1,nan\n2,nan\n3,nan\n", "holes.csv",
                                         io::MissingCells::kKeepAsNaN);
  try {
    SeriesFromTable(table, Options());
    FAIL() << "no error";
  } catch (const NothingToIdentify& e) {
    EXPECT_NE(std::string(e.what()).find("holes.csv: 4 data rows"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SeriesFromTable(io::CsvTable::Parse("u,y\n0,1\n", "x"), Options("t")),
               io::CsvError);  // no time column
}

TEST(SeriesFromTable, ALogAtSeveralRatesIsReadOnTheSlowestColumnsGrid) {
  // y every 10 ms, u every 40 ms (empty cells between): the grid is u's 25 Hz, u never a gap.
  std::string csv = "t,y,u\n";
  for (int i = 0; i <= 200; ++i)
    csv += std::to_string(i * 0.01) + "," + std::to_string(i * 0.01) + "," +
           (i % 4 == 0 ? std::to_string(2 * i * 0.01) : std::string("")) + "\n";
  const auto table = io::CsvTable::Parse(csv, "rates.csv", io::MissingCells::kKeepAsNaN);
  SeriesReport r;
  const Series s = SeriesFromTable(table, Options("t"), &r);
  EXPECT_NEAR(r.rate_hz, 25.0, 1e-6);
  EXPECT_TRUE(r.rate_chosen);
  EXPECT_EQ(r.slowest, "u");
  EXPECT_EQ(s.samples(), 51);
  EXPECT_EQ(r.missing, 0);
  // Forced onto 100 Hz, u is far slower than the grid: the error names it and the fix.
  SeriesOptions fast = Options("t", 1);
  fast.rate_hz = 100;
  try {
    SeriesFromTable(table, fast);
    FAIL() << "no error";
  } catch (const NothingToIdentify& e) {
    EXPECT_NE(std::string(e.what()).find("'u' is logged at 25 Hz"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--rate 25"), std::string::npos) << e.what();
  }
}

TEST(SeriesFromTable, FlagsAreHeldWindowsAndConditionsCut) {
  // A 0/1 column is a flag: held on a grid, never 0.5. "on" is 1 from 1 s on.
  std::string csv = "t,y,u,on\n";
  for (int i = 0; i <= 40; ++i)
    csv += std::to_string(i * 0.1) + "," + std::to_string(i) + "," + std::to_string(i % 3) + "," +
           (i >= 10 ? "1" : "0") + "\n";
  const auto table = io::CsvTable::Parse(csv, "flag.csv", io::MissingCells::kKeepAsNaN);
  SeriesOptions o = Options("t");
  o.rate_hz = 20;  // between the rows: a linear column is interpolated, the flag held
  o.keep = timeseries::ParseKeepCondition("on==1");
  SeriesReport r;
  const Series s = SeriesFromTable(table, o, &r);
  EXPECT_GT(r.cut_by_condition, 0);
  EXPECT_NEAR(r.first_s, 1.0, 1e-9);  // the condition held from 1 s on
  ASSERT_EQ(r.columns.size(), 3u);
  EXPECT_TRUE(r.columns[2].held);
  // A window on the time axis.
  SeriesOptions w = Options("t");
  w.from_s = 2.0;
  w.to_s = 3.0;
  SeriesReport rw;
  EXPECT_EQ(SeriesFromTable(table, w, &rw).samples(), 11);
  EXPECT_NEAR(rw.first_s, 2.0, 1e-9);
  // A window that keeps nothing, and a condition that never holds: nothing to identify.
  w.from_s = 10;
  w.to_s = 11;
  EXPECT_THROW(SeriesFromTable(table, w), NothingToIdentify);
  o.keep = timeseries::ParseKeepCondition("on==2");
  EXPECT_THROW(SeriesFromTable(table, o), NothingToIdentify);
  // Without a time column, a window needs the rows' rate.
  SeriesOptions rows = Options();
  rows.from_s = 1;
  EXPECT_THROW(SeriesFromTable(table, rows), io::CsvError);
  rows.rate_hz = 10;
  EXPECT_EQ(SeriesFromTable(table, rows).samples(), 31);
}

TEST(SeriesFromTable, TheTimeUnitComesFromTheColumnsName) {
  EXPECT_DOUBLE_EQ(TimeUnitFromName("time_ms"), 1e-3);
  EXPECT_DOUBLE_EQ(TimeUnitFromName("t [ms]"), 1e-3);
  EXPECT_DOUBLE_EQ(TimeUnitFromName("timestamp_us"), 1e-6);
  EXPECT_DOUBLE_EQ(TimeUnitFromName("t_s"), 1.0);
  // Milliseconds read as such give the true rate.
  const auto table = io::CsvTable::Parse("time_ms,y,u\n0,0,0\n10,1,1\n20,2,0\n30,3,1\n", "ms.csv",
                                         io::MissingCells::kKeepAsNaN);
  SeriesOptions o = Options("time_ms");
  o.time_unit_s = TimeUnitFromName("time_ms");
  SeriesReport r;
  SeriesFromTable(table, o, &r);
  EXPECT_NEAR(r.rate_hz, 100.0, 1e-6);
}

TEST(Segments, NoRegressorCrossesABreakAndTheFreeRunRestartsFromMeasuredValues) {
  RegressorSpec spec;
  spec.outputs = {"y"};
  spec.inputs = {"u"};
  spec.output_lags = 2;
  spec.input_lags = 1;
  Series s;
  s.outputs = Eigen::VectorXd::LinSpaced(10, 0, 9);
  s.inputs = Eigen::VectorXd::Zero(10);
  s.breaks = {5};
  EXPECT_EQ(TargetRows(spec, s), (std::vector<Eigen::Index>{2, 3, 4, 7, 8, 9}));
  EXPECT_EQ(BuildRegression(spec, s).x.rows(), 6);
  // A predictor that returns y(t−1) + 1 is exact on this ramp, within each segment, because the
  // second segment's simulation starts again from its own measured first rows.
  const Predictor next = [](const Eigen::VectorXd& x) {
    return Eigen::VectorXd::Constant(1, x(0) + 1.0);
  };
  const Eigen::MatrixXd sim = SimulateFreeRun(spec, s, next);
  EXPECT_EQ(sim.col(0), Targets(spec, s).col(0));
  s.outputs(5) = 100;  // the second segment's first measurement
  s.outputs(6) = 101;
  EXPECT_DOUBLE_EQ(SimulateFreeRun(spec, s, next)(3, 0), 102.0);
}

}  // namespace
}  // namespace odonata::sysid
