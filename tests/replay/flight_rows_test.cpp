// A recorded flight as the rows odonata-replay sends: which columns, at what times, and what is
// refused with the file's name.
#include "replay/flight_rows.hpp"

#include "timeseries/nothing_to_identify.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace odonata::replay {
namespace {

std::string Error(const io::CsvTable& t, const FlightRowsOptions& o) {
  try {
    FlightRowsFromTable(t, o);
  } catch (const io::CsvError& e) {
    return e.what();
  }
  return "";
}

TEST(FlightRows, EveryColumnButTimeAndSeqByDefaultAtTheFilesTimes) {
  const auto t =
      io::CsvTable::Parse("seq,t_s,vz,u\n0,10.0,1,2\n1,10.02,3,4\n2,10.05,5,6\n", "f.csv");
  const FlightRows f = FlightRowsFromTable(t, {});
  EXPECT_EQ(f.names, (std::vector<std::string>{"vz", "u"}));
  ASSERT_EQ(f.rows.size(), 3u);
  EXPECT_NEAR(f.times_s[2], 0.05, 1e-12);  // from the first row's time
  EXPECT_EQ(f.rows[1], (std::vector<double>{3, 4}));
  EXPECT_EQ(f.source, "f.csv");
}

TEST(FlightRows, ChosenSignalsInTheirOrderAndARateWithoutTime) {
  const auto t = io::CsvTable::Parse("a,b,c\n1,2,3\n4,5,6\n", "f.csv");
  FlightRowsOptions o;
  o.signals = {"c", "a"};
  o.rate_hz = 50;
  const FlightRows f = FlightRowsFromTable(t, o);
  EXPECT_EQ(f.rows[1], (std::vector<double>{6, 4}));
  EXPECT_DOUBLE_EQ(f.times_s[1], 0.02);
}

// Issue 61: a signal named twice is refused, as a ULog's export refuses it.
TEST(FlightRows, ASignalNamedTwiceIsRefused) {
  const auto t = io::CsvTable::Parse("u,y\n1,2\n3,4\n", "f.csv");
  FlightRowsOptions o;
  o.signals = {"u", "u"};
  EXPECT_EQ(Error(t, o), "f.csv: signal 'u' is asked for twice");
}

// Issue 57: a window in seconds on the file's time axis, and a condition whose failing rows go
// out as gaps; a window that keeps nothing is nothing to send.
TEST(FlightRows, AWindowAndAConditionChooseTheRowsSent) {
  const auto t = io::CsvTable::Parse(
      "t_s,a,landed\n10,1,1\n10.1,2,0\n10.2,3,0\n10.3,4,1\n10.4,5,0\n", "f.csv");
  FlightRowsOptions o;
  o.from_s = 10.1;
  o.to_s = 10.35;
  o.keep = timeseries::ParseKeepCondition("landed==0");
  const FlightRows f = FlightRowsFromTable(t, o);
  EXPECT_EQ(f.names, (std::vector<std::string>{"a"}));  // the condition's column is not sent
  ASSERT_EQ(f.rows.size(), 3u);
  EXPECT_DOUBLE_EQ(f.times_s[0], 0.0);
  EXPECT_NEAR(f.times_s[2], 0.2, 1e-12);
  EXPECT_TRUE(f.Complete(0));
  EXPECT_FALSE(f.Complete(2));  // landed: a gap
  o.from_s = 20;
  o.to_s = 21;
  EXPECT_THROW(FlightRowsFromTable(t, o), timeseries::NothingToIdentify);
}

TEST(FlightRows, ARowWithAGapIsNotCompleteAndStaysInPlace) {
  const auto t =
      io::CsvTable::Parse("t_s,a\n0,1\n0.01,\n0.02,3\n", "f.csv", io::MissingCells::kKeepAsNaN);
  const FlightRows f = FlightRowsFromTable(t, {});
  ASSERT_EQ(f.rows.size(), 3u);
  EXPECT_TRUE(f.Complete(0));
  EXPECT_FALSE(f.Complete(1));
  EXPECT_TRUE(f.Complete(2));
}

TEST(FlightRows, AMissingColumnOrTimeThatDoesNotIncreaseIsNamed) {
  const auto t = io::CsvTable::Parse("t_s,a\n0,1\n0,2\n", "f.csv");
  FlightRowsOptions o;
  o.signals = {"b"};
  EXPECT_NE(Error(t, o).find("no column named 'b' (columns: t_s, a)"), std::string::npos)
      << Error(t, o);
  EXPECT_NE(Error(t, {}).find("'t_s' row 2: the time stamps must be finite and increase"),
            std::string::npos)
      << Error(t, {});
}

}  // namespace
}  // namespace odonata::replay
