// odonata-logger export: its runs are the identifier's (a plant restart it confirms starts one); a
// trailing run of states alone is named as such, and the run that has commands still exports.
#include "log_export/log_csv_export.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "io/csv_table.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/wing_command_message.hpp"
#include "odonata/signals_t.hpp"

namespace odonata::log_export {
namespace {

class TempDir {
 public:
  TempDir() {
    char tmpl[] = "/tmp/odonata_export_test_XXXXXX";
    path_ = mkdtemp(tmpl);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

template <typename T>
void Write(lcm::LogFile& log, const std::string& channel, const T& msg, int64_t utime) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
  lcm::LogEvent ev{};
  ev.timestamp = utime;
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(buf.size());
  ev.data = buf.data();
  ASSERT_EQ(log.writeEvent(&ev), 0);
}

odonata::plant_state_t State(int64_t seq, int64_t command_seq) {
  pipeline::PlantSample s;
  s.seq = seq;
  s.command_seq = command_seq;
  s.output.time_s = 0.01 * static_cast<double>(seq);
  return messages::ToStateMessage(s, seq);
}

// What the logged plant does besides answering commands 0…n−1 with states 1…n.
struct Shape {
  /// A new plant's state 0 at the end, as often: a restarted plant repeats it while nothing
  /// commands it (1: a lone stale or forged one).
  int restart_zeros = 0;
  /// A repeat of state 0 right after command 0: a lockstep plant re-publishes its state 0 until
  /// it has read the first command, so on a busy machine a repeat sent just before is logged
  /// after it.
  bool late_repeat = false;
  /// A fresh state 0 after this state (-1: none): a stale or forged one mid-run.
  int stray_zero_after = -1;
};

Shape RestartZeros(int count) {
  Shape s;
  s.restart_zeros = count;
  return s;
}
Shape LateRepeat() {
  Shape s;
  s.late_repeat = true;
  return s;
}
Shape StrayZeroAfter(int k) {
  Shape s;
  s.stray_zero_after = k;
  return s;
}

std::string WriteLog(const std::string& dir, int n, const Shape& shape = {}) {
  const std::string path = dir + "/log.00000";
  lcm::LogFile log(path, "w");
  pipeline::CommandSchedule schedule;
  schedule.sample_period_s = 0.01;
  schedule.commands.assign(static_cast<std::size_t>(n), plant::CommandMatrix::Constant(0.5));
  int64_t t = 1;
  Write(log, "DIMAV_STATE", State(0, -1), t++);
  for (int k = 0; k < n; ++k) {
    Write(log, "DIMAV_COMMAND",
          messages::ToCommandMessage(schedule, static_cast<std::size_t>(k), 0), t++);
    if (shape.late_repeat && k == 0) Write(log, "DIMAV_STATE", State(0, -1), t++);
    Write(log, "DIMAV_STATE", State(k + 1, k), t++);
    if (k + 1 == shape.stray_zero_after) Write(log, "DIMAV_STATE", State(0, -1), t++);
  }
  for (int i = 0; i < shape.restart_zeros; ++i) Write(log, "DIMAV_STATE", State(0, -1), t++);
  return path;
}

// A run of states alone (a plant restarted after the last command, or reset twice when a RESET
// was resent over a lossy link) is named when asked for by number, and skipped when runs are
// counted from the end: "the last run" is the last one with samples (odonata-run's --run -2 of a
// real-time run at 5 % loss once failed on one).
TEST(LogCsvExport, ARunWithoutCommandsIsNamedAndSkippedWhenCountingFromTheEnd) {
  const TempDir dir;
  const std::string log = WriteLog(dir.path(), 20, RestartZeros(3));
  const std::string csv = dir.path() + "/samples.csv";
  ExportOptions second;
  second.run = 1;
  try {
    ExportLogToCsv({log}, csv, second);
    FAIL() << "the state-only run exported";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("run 1 of 2 has no commands"), std::string::npos) << what;
    EXPECT_NE(what.find("--run"), std::string::npos) << what;
  }
  ExportOptions before_last;
  before_last.run = -2;
  EXPECT_THROW(ExportLogToCsv({log}, csv, before_last), std::runtime_error)
      << "one run with samples: there is none before it";
  const ExportSummary s = ExportLogToCsv({log}, csv, ExportOptions{});  // -1: the last with samples
  EXPECT_EQ(s.runs, 2);
  EXPECT_EQ(s.exported_run, 0);
  EXPECT_EQ(s.rows, 20);
  std::ifstream in(csv);
  long lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_EQ(lines, 21);  // the header and one row per sample
}

// The repeat is the same run, as the identifier pairs it (pipeline/sample_pairer.hpp): it used to
// open a second run without command 0, whose export lacked sample 0, and integration_packet_loss
// saw 499 of 500 samples under two CPU hogs.
TEST(LogCsvExport, AStateZeroRepeatedAfterTheFirstCommandIsTheSameRun) {
  const TempDir dir;
  const std::string log = WriteLog(dir.path(), 20, LateRepeat());
  const ExportSummary s = ExportLogToCsv({log}, dir.path() + "/samples.csv", ExportOptions{});
  EXPECT_EQ(s.runs, 1);
  EXPECT_EQ(s.rows, 20);
  EXPECT_EQ(s.incomplete, 0);
}

// A fresh state 0 is a new run only once the plant confirms it, as for the identifier
// (docs/lcm.md §10): a lone stale or forged one, mid-run or at the end, used to cut the run in
// two, and the default export (the last run) wrote only the part after it, or nothing.
TEST(LogCsvExport, ALoneStateZeroDoesNotCutTheRun) {
  const TempDir dir;
  for (const Shape shape : {StrayZeroAfter(10), RestartZeros(1)}) {
    const std::string log = WriteLog(dir.path(), 20, shape);
    const ExportSummary s = ExportLogToCsv({log}, dir.path() + "/samples.csv", ExportOptions{});
    EXPECT_EQ(s.runs, 1) << shape.stray_zero_after;
    EXPECT_EQ(s.rows, 20) << shape.stray_zero_after;
    EXPECT_EQ(s.incomplete, 0) << shape.stray_zero_after;
    EXPECT_EQ(s.rejected, 0) << shape.stray_zero_after;
  }
}

TEST(LogCsvExport, ALogWithoutCommandsSaysSo) {
  const TempDir dir;
  const std::string log = WriteLog(dir.path(), 0);
  try {
    ExportLogToCsv({log}, dir.path() + "/samples.csv", ExportOptions{});
    FAIL() << "a log without commands exported";
  } catch (const std::runtime_error& e) {
    // And says what to do when the log is a vehicle's own (issue 57: no hint before).
    EXPECT_STREQ(e.what(),
                 "no commands on DIMAV_COMMAND in the log: it holds no simulated DI-MAV run; a "
                 "vehicle's signals (signals_t) export with --signals");
  }
}

// A vehicle that publishes its own t_s (issue 48 point 3): the export adds seq and t_s, so a
// header of seq,t_s,t_s,… would be refused by every CSV reader. The vehicle's t_s is written as
// t_s_vehicle, said in the header comment and in the summary, and the file reads.
TEST(LogCsvExport, AVehicleSignalNamedLikeAnAddedColumnIsRenamed) {
  TempDir dir;
  const std::string log_path = dir.path() + "/log.00";
  {
    lcm::LogFile log(log_path, "w");
    for (int64_t k = 0; k < 5; ++k) {
      odonata::signals_t m;
      m.utime = 1000000 + 10000 * k;
      m.seq = k;
      m.source = "flapper";
      m.names = {"t_s", "m1", "seq", "t_s_vehicle"};
      m.values = {0.01 * static_cast<double>(k), 0.5, 7.0, 9.0};
      m.num_signals = 4;
      Write(log, "VEHICLE_SIGNALS", m, m.utime);
    }
  }
  const std::string csv = dir.path() + "/out.csv";
  const SignalsExportSummary s = ExportSignalsToCsv({log_path}, "VEHICLE_SIGNALS", csv);
  EXPECT_EQ(s.rows, 5);
  ASSERT_EQ(s.renamed.size(), 3u);
  EXPECT_EQ(s.renamed[0], (std::pair<std::string, std::string>{"t_s", "t_s_vehicle"}));
  EXPECT_EQ(s.renamed[1], (std::pair<std::string, std::string>{"seq", "seq_vehicle"}));
  // Its own t_s_vehicle comes after the renamed t_s: it gets the next free name.
  EXPECT_EQ(s.renamed[2],
            (std::pair<std::string, std::string>{"t_s_vehicle", "t_s_vehicle_vehicle"}));
  const io::CsvTable t = io::CsvTable::Read(csv);
  EXPECT_EQ(t.names(), (std::vector<std::string>{"seq", "t_s", "t_s_vehicle", "m1", "seq_vehicle",
                                                 "t_s_vehicle_vehicle"}));
  EXPECT_DOUBLE_EQ(t.Column("t_s_vehicle")[3], 0.03);
  EXPECT_DOUBLE_EQ(t.Column("seq_vehicle")[0], 7.0);
  std::ifstream in(csv);
  std::string first;
  std::getline(in, first);
  // The header comes first, with no comment line before it: Python's csv.DictReader, pandas and
  // Octave read the file as it is (the renames are in the summary, which the tool prints).
  EXPECT_EQ(first, "seq,t_s,t_s_vehicle,m1,seq_vehicle,t_s_vehicle_vehicle") << first;
}

TEST(CsvTable, ADuplicateColumnNameSaysWhichAndHowToFixIt) {
  try {
    io::CsvTable::Parse("seq,t_s,t_s,m1\n0,0,0,1\n", "flight.csv");
    FAIL() << "a duplicate column was accepted";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'t_s' appears twice"), std::string::npos) << what;
    EXPECT_NE(what.find("columns 2 and 3"), std::string::npos) << what;
    EXPECT_NE(what.find("rename one of them"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace odonata::log_export
