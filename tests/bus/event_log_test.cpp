// EventLogWriter never overwrites and never writes an event no reader can read back;
// ForEachLogEvent reads a log to its end or says it is damaged.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "bus/event_log_reader.hpp"
#include "bus/event_log_writer.hpp"

namespace odonata::bus {
namespace {

namespace fs = std::filesystem;

class EventLogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/odonata_event_log_test_XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `n` events of 1…n bytes on channel "A" and returns the files.
  std::vector<std::string> Record(const std::string& prefix, int n) const {
    EventLogWriter w(prefix, 0);
    for (int i = 1; i <= n; ++i) {
      const std::string data(static_cast<std::size_t>(i), static_cast<char>('a' + i % 26));
      w.Write(i, "A", data.data(), i);
    }
    w.Close();
    return w.files();
  }

  static std::vector<std::string> Events(const std::vector<std::string>& files) {
    std::vector<std::string> out;
    ForEachLogEvent(files, [&out](const lcm::LogEvent& ev) {
      out.emplace_back(static_cast<const char*>(ev.data), static_cast<std::size_t>(ev.datalen));
    });
    return out;
  }

  static std::string Slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }

  std::string dir_;
};

TEST_F(EventLogTest, ARestartNumbersOnAndKeepsTheEarlierRecording) {
  const std::string prefix = dir_ + "/run";
  const auto first = Record(prefix, 5);
  ASSERT_EQ(first, std::vector<std::string>{prefix + ".00000"});
  const std::string before = Slurp(first[0]);
  const auto second = Record(prefix, 3);
  ASSERT_EQ(second, std::vector<std::string>{prefix + ".00001"});
  EXPECT_EQ(Slurp(first[0]), before);
  EXPECT_EQ(Events(first).size(), 5u);
  EXPECT_EQ(Events({first[0], second[0]}).size(), 8u);
  // A prefix that is only the start of other names does not count them.
  EXPECT_EQ(Record(dir_ + "/ru", 1), std::vector<std::string>{dir_ + "/ru.00000"});
}

TEST_F(EventLogTest, NeverWritesThroughASymlinkAndCreatesDirectories) {
  const std::string victim = dir_ + "/victim.txt";
  std::ofstream(victim) << "precious";
  const std::string prefix = dir_ + "/new/sub/log";
  fs::create_directories(dir_ + "/new/sub");
  fs::create_symlink(victim, prefix + ".00000");
  const auto files = Record(prefix, 2);
  EXPECT_EQ(files, std::vector<std::string>{prefix + ".00001"});
  EXPECT_EQ(Slurp(victim), "precious");
  const auto deep = Record(dir_ + "/a/b/c/log", 1);
  EXPECT_TRUE(fs::exists(deep[0]));
}

TEST_F(EventLogTest, AMalformedEventIsRefusedAndTheLogStaysReadable) {
  const std::string prefix = dir_ + "/log";
  EventLogWriter w(prefix, 0);
  w.Write(1, "A", "xy", 2);
  const char byte = 'z';
  EXPECT_THROW(w.Write(2, "A", &byte, -1), std::invalid_argument);
  EXPECT_THROW(w.Write(3, "A", nullptr, 4), std::invalid_argument);
  EXPECT_THROW(w.Write(4, "", &byte, 1), std::invalid_argument);
  EXPECT_THROW(w.Write(5, std::string(64, 'C'), &byte, 1), std::invalid_argument);
  w.Write(6, "B", &byte, 1);
  w.Close();
  EXPECT_EQ(w.events(), 2);
  EXPECT_EQ(Events(w.files()), (std::vector<std::string>{"xy", "z"}));
}

// Damage does not end the reading: every readable event is read and the lost bytes counted;
// --strict (strict) makes it an error naming the file.
TEST_F(EventLogTest, ADamagedLogIsReadPastItsDamageAndCounted) {
  const auto files = Record(dir_ + "/log", 20);
  const std::string whole = Slurp(files[0]);
  ASSERT_EQ(Events(files).size(), 20u);
  // Event i holds 28 + 1 + i bytes: events 1-3 end at byte 93, event 4 at 126.
  const std::string tail = dir_ + "/tail", middle = dir_ + "/middle", seam = dir_ + "/seam";
  std::ofstream(tail, std::ios::binary) << whole << "garbage";
  std::ofstream(middle, std::ios::binary)
      << whole.substr(0, 100) << "\x01\x02\x03garbage" << whole.substr(100);
  std::ofstream(seam, std::ios::binary)
      << whole.substr(0, 93) << "\x01\x02\x03garbage" << whole.substr(93);
  for (const std::string& bad : {tail, middle, seam}) {
    std::vector<std::string> got;
    const LogReadReport r = ForEachLogEvent({bad}, [&got](const lcm::LogEvent& ev) {
      got.emplace_back(static_cast<const char*>(ev.data), static_cast<std::size_t>(ev.datalen));
    });
    // In the middle the garbage lands in event 4's header, which is lost with it.
    const long expected = bad == middle ? 19 : 20;
    EXPECT_EQ(r.events, expected) << bad;
    EXPECT_EQ(static_cast<long>(got.size()), expected) << bad;
    EXPECT_EQ(r.bytes_lost, bad == tail ? 7 : bad == middle ? 33 + 10 : 10) << bad;
    EXPECT_EQ(r.damaged_files, 1) << bad;
    EXPECT_EQ(got.back(), std::string(20, static_cast<char>('a' + 20 % 26))) << bad;
    try {
      ForEachLogEvent(
          {bad}, [](const lcm::LogEvent&) {}, true);
      ADD_FAILURE() << bad << " was read as if whole with strict";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("damaged event log"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
  // Garbage at a seam costs no event (lcm::LogFile drops the whole event before it).
  std::vector<std::string> at_seam;
  ForEachLogEvent({seam}, [&at_seam](const lcm::LogEvent& ev) {
    at_seam.emplace_back(static_cast<const char*>(ev.data), static_cast<std::size_t>(ev.datalen));
  });
  EXPECT_EQ(at_seam, Events(files));
  // A forged header whose channel is 5000 bytes long (lcm's reader asserts on it) is garbage.
  std::string forged = whole.substr(0, 93);
  forged += std::string("\xED\xA1\xDA\x01", 4) + std::string(16, '\0') +
            std::string("\x00\x00\x13\x88\x00\x00\x00\x01", 8) + whole.substr(93);
  const std::string forged_path = dir_ + "/forged";
  std::ofstream(forged_path, std::ios::binary) << forged;
  EXPECT_EQ(Events({forged_path}), Events(files));
  EXPECT_THROW(Events({dir_ + "/missing"}), std::runtime_error);
  // A whole log is whole, strict or not.
  const LogReadReport clean = ForEachLogEvent(
      files, [](const lcm::LogEvent&) {}, true);
  EXPECT_EQ(clean.events, 20);
  EXPECT_EQ(clean.bytes_lost, 0);
}

// A logger killed while writing leaves its last event cut off: every whole event before it is
// read, whether the cut falls in the last event's data or in its header.
TEST_F(EventLogTest, ACutOffLastEventLeavesTheEventsBeforeIt) {
  const auto files = Record(dir_ + "/log", 20);
  const std::string whole = Slurp(files[0]);
  const std::size_t last = 28 + 1 + 20;  // header, channel "A", 20 bytes of data
  for (const std::size_t keep : {last - 7, std::size_t{10}, std::size_t{2}}) {
    const std::string cut = dir_ + "/cut" + std::to_string(keep);
    std::ofstream(cut, std::ios::binary) << whole.substr(0, whole.size() - last + keep);
    const auto events = Events({cut});
    ASSERT_EQ(events.size(), 19u) << keep << " bytes of the last event kept";
    EXPECT_EQ(ForEachLogEvent({cut}, [](const lcm::LogEvent&) {}).bytes_lost,
              static_cast<int64_t>(keep));
    EXPECT_THROW(ForEachLogEvent(
                     {cut}, [](const lcm::LogEvent&) {}, true),
                 std::runtime_error);
    EXPECT_EQ(events.back(), std::string(19, static_cast<char>('a' + 19 % 26)));
  }
}

}  // namespace
}  // namespace odonata::bus
