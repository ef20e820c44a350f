// MonitorNode over memq://: the published accuracy_t equals the metrics computed directly, for
// both modes, over the window and since start; the accuracy-drop warning comes and goes; a
// forged far-ahead prediction is dropped without touching the score.
#include "monitor_node.hpp"

#include <gtest/gtest.h>
#include <limits>

#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "metrics/accuracy.hpp"
#include "support/memq_bus.hpp"

namespace odonata::monitor {
namespace {

void Pump(bus::BusNode& bus, int ms = 1) { testing::Pump(bus, ms); }

double Y(int64_t k) { return std::sin(0.03 * static_cast<double>(k)); }
double OneStep(int64_t k) { return Y(k) + 0.01 * std::cos(1.7 * static_cast<double>(k)); }
double FreeRun(int64_t k) { return 0.9 * Y(k) + 0.05; }
// The identifier's live ARX baseline: worse than the fuzzy model in both modes.
double Arx(int64_t k) { return 0.8 * Y(k) + 0.1; }

class MonitorNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    bus_ = std::make_unique<bus::BusNode>(testing::MemqOptions("odonata-monitor"));
    bus_->Subscribe<odonata::accuracy_t>(bus_->channels().accuracy,
                                         [this](const auto& m) { accuracy_.push_back(m); });
    MonitorOptions mo;
    mo.scoring.window_samples = 100;
    mo.publish_hz = 1000.0;
    mo.print_period_s = 1e6;
    mo.scoring.warn_fit_percent = 80.0;
    node_ = std::make_unique<MonitorNode>(*bus_, mo);
  }
  void Send(int64_t k, double predicted, double free_run, const std::string& name = "roll_rad") {
    odonata::prediction_t p{};
    p.seq = k;
    p.sample = k;
    p.num_outputs = 1;
    p.names = {name};
    p.measured = {Y(k)};
    p.predicted = {predicted};
    p.free_run = {free_run};
    p.next = {0.0};
    p.rules = {3};
    p.max_entropy = {0.2};
    p.arx_predicted = {Arx(k)};
    p.arx_free_run = {Arx(k) - 0.05};
    p.linear_share = {k % 4 == 0 ? 0.5 : 0.0};
    p.learning = 1;
    bus_->Publish(bus_->channels().prediction, p);
    Pump(*bus_);
  }

  std::unique_ptr<bus::BusNode> bus_;
  std::unique_ptr<MonitorNode> node_;
  std::vector<odonata::accuracy_t> accuracy_;
};

TEST_F(MonitorNodeTest, PublishesWindowAndTotalAccuracyOfBothModes) {
  const int n = 300;
  for (int64_t k = 0; k < n; ++k) Send(k, OneStep(k), FreeRun(k));
  accuracy_.clear();
  Pump(*bus_, 5);
  ASSERT_FALSE(accuracy_.empty());
  const odonata::accuracy_t& a = accuracy_.back();
  ASSERT_EQ(a.num_outputs, 1);
  EXPECT_EQ(a.names[0], "roll_rad");
  EXPECT_EQ(a.total_samples, n);
  EXPECT_EQ(a.window_samples, 100);
  EXPECT_EQ(a.last_sample, n - 1);
  EXPECT_EQ(a.rules[0], 3);

  Eigen::VectorXd y(n), one(n), free(n);
  for (int k = 0; k < n; ++k) {
    y(k) = Y(k);
    one(k) = OneStep(k);
    free(k) = FreeRun(k);
  }
  // Each published (FIT, VAF, RMSE) triple against the same figures computed here.
  const auto expect = [](const char* what, double fit, double vaf, double rmse, const auto& score) {
    EXPECT_NEAR(fit, score.fit_percent, 1e-6) << what;
    EXPECT_NEAR(vaf, score.vaf_percent, 1e-6) << what;
    EXPECT_NEAR(rmse, score.rmse, 1e-9) << what;
  };
  expect("total one-step", a.total_fit_one_step[0], a.total_vaf_one_step[0],
         a.total_rmse_one_step[0], metrics::Score(y, one));
  expect("window one-step", a.window_fit_one_step[0], a.window_vaf_one_step[0],
         a.window_rmse_one_step[0], metrics::Score(y.tail(100), one.tail(100)));
  expect("total free-run", a.total_fit_free_run[0], a.total_vaf_free_run[0],
         a.total_rmse_free_run[0], metrics::Score(y, free));
  expect("window free-run", a.window_fit_free_run[0], a.window_vaf_free_run[0],
         a.window_rmse_free_run[0], metrics::Score(y.tail(100), free.tail(100)));
  // The live ARX's FIT over the same samples, beside the fuzzy model's.
  Eigen::VectorXd arx(n), arx_free(n);
  for (int k = 0; k < n; ++k) {
    arx(k) = Arx(k);
    arx_free(k) = Arx(k) - 0.05;
  }
  EXPECT_NEAR(a.total_fit_one_step_arx[0], metrics::Score(y, arx).fit_percent, 1e-6);
  EXPECT_NEAR(a.window_fit_one_step_arx[0], metrics::Score(y.tail(100), arx.tail(100)).fit_percent,
              1e-6);
  EXPECT_NEAR(a.total_fit_free_run_arx[0], metrics::Score(y, arx_free).fit_percent, 1e-6);
  EXPECT_NEAR(a.window_fit_free_run_arx[0],
              metrics::Score(y.tail(100), arx_free.tail(100)).fit_percent, 1e-6);
  EXPECT_FALSE(node_->BehindArx("roll_rad"));
  EXPECT_FALSE(node_->Summary()["outputs"]["roll_rad"]["behind_arx"].get<bool>());
  // Every fourth sample lay outside the model's data (prediction_t.linear_share > 0): counted.
  long outside = 0;
  for (int k = 0; k < n; ++k) outside += k % 4 == 0;
  EXPECT_EQ(node_->Summary()["outputs"]["roll_rad"]["samples_outside"].get<long>(), outside);
}

// A model that does no better than the live ARX is marked, and unmarked when it does again.
// Issue 57: a signal name longer than its column goes on a line of its own, every line of the
// table keeps to 80 columns, and a diverging free run prints as "diverges", as in every tool.
TEST_F(MonitorNodeTest, ALongNameHasItsOwnLineAndADivergingRunSaysSo) {
  const std::string name = "vehicle_angular_velocity.xyz[1]";
  for (int64_t k = 0; k < 150; ++k) Send(k, OneStep(k), 1e3 * static_cast<double>(k), name);
  ::testing::internal::CaptureStdout();
  bus_->Stop(0);  // the shutdown prints the table once more
  const std::string table = ::testing::internal::GetCapturedStdout();
  // The name on its own line, its rows below it aligned under the header's columns.
  const std::size_t at = table.find("\n" + name + "\n");
  ASSERT_NE(at, std::string::npos) << table;
  EXPECT_EQ(table.compare(at + name.size() + 2, 15, std::string(14, ' ') + "3"), 0) << table;
  std::size_t begin = 0;
  while (begin < table.size()) {
    const std::size_t end = std::min(table.find('\n', begin), table.size());
    const std::string line = table.substr(begin, end - begin);
    // The table's columns (a row's notes, "25% outside", "<= ARX", may run past them).
    if (line.find("errors ") == std::string::npos) {
      EXPECT_LE(std::min(line.size(), line.find("  ", 60)), 80u) << line;
    }
    begin = end + 1;
  }
  EXPECT_NE(table.find("diverges"), std::string::npos) << table;
}

TEST_F(MonitorNodeTest, MarksAWindowWhereTheFuzzyModelDoesNotBeatTheLiveArx) {
  for (int64_t k = 0; k < 150; ++k) Send(k, OneStep(k), FreeRun(k));
  EXPECT_FALSE(node_->BehindArx("roll_rad"));
  for (int64_t k = 150; k < 300; ++k) Send(k, Arx(k) - 0.2, FreeRun(k));  // worse than linear
  EXPECT_TRUE(node_->BehindArx("roll_rad"));
  for (int64_t k = 300; k < 450; ++k) Send(k, OneStep(k), FreeRun(k));
  EXPECT_FALSE(node_->BehindArx("roll_rad"));
}

TEST_F(MonitorNodeTest, WarnsWhenTheWindowFitDropsAndClearsWhenItRecovers) {
  for (int64_t k = 0; k < 150; ++k) Send(k, OneStep(k), FreeRun(k));
  EXPECT_FALSE(node_->Warned("roll_rad"));
  for (int64_t k = 150; k < 250; ++k) Send(k, 0.0, 0.0);  // the model lost it
  EXPECT_TRUE(node_->Warned("roll_rad"));
  for (int64_t k = 250; k < 400; ++k) Send(k, OneStep(k), FreeRun(k));
  EXPECT_FALSE(node_->Warned("roll_rad"));
}

// The change alarm: quiet while the model is steady, raised within one alarm window (100
// samples) of a sudden loss, cleared when accuracy is back, each event in the summary.
TEST_F(MonitorNodeTest, RaisesTheChangeAlarmWithinAWindowAndReportsTheRecovery) {
  const auto bias = [](int64_t k) { return k >= 1500 && k < 1800 ? 0.3 : 0.0; };
  int64_t raised = -1, cleared = -1;
  for (int64_t k = 0; k < 2600; ++k) {
    Send(k, OneStep(k) + bias(k), FreeRun(k));
    if (raised < 0 && node_->Alarmed("roll_rad")) raised = k;
    if (raised >= 0 && cleared < 0 && !node_->Alarmed("roll_rad")) cleared = k;
  }
  ASSERT_GE(raised, 1500) << "no alarm before the change";
  EXPECT_LT(raised, 1600) << "within one window (1 s at 100 Hz) of the change";
  ASSERT_GT(cleared, 1800);
  EXPECT_LT(cleared, 2000) << "within a window of the model's return";
  const nlohmann::json events = node_->Summary()["outputs"]["roll_rad"]["alarm_events"];
  ASSERT_EQ(events.size(), 2u) << events.dump();
  EXPECT_EQ(events[0]["kind"], "alarm");
  EXPECT_EQ(events[0]["sample"].get<int64_t>(), raised);
  EXPECT_EQ(events[1]["kind"], "recovered");
  EXPECT_EQ(events[1]["sample"].get<int64_t>(), cleared);
  EXPECT_GT(events[0]["reference_fit"].get<double>(), 95.0);
}

TEST_F(MonitorNodeTest, AForgedFarAheadPredictionIsDroppedAndTheScoreGoesOn) {
  for (int64_t k = 0; k < 50; ++k) Send(k, OneStep(k), FreeRun(k));
  Send(int64_t{1} << 40, 0.0, 0.0);
  Send(49 + 900000, 0.0, 0.0);  // within the window, but an unconfirmed leap
  EXPECT_EQ(bus_->stats().dropped + bus_->stats().decode_errors, 2);
  for (int64_t k = 50; k < 100; ++k) Send(k, OneStep(k), FreeRun(k));
  const nlohmann::json s = node_->Summary();
  EXPECT_FALSE(s.contains("previous_runs"));
  EXPECT_EQ(s["gaps"], 0);
  EXPECT_EQ(s["last_sample"], 99);
  EXPECT_EQ(s["outputs"]["roll_rad"]["one_step"]["samples"], 100);
}

// A real-time plant's skips and repeats reach the monitor's summary as the heartbeat reports them.
TEST_F(MonitorNodeTest, SummaryCarriesAPlantsSkippedAndRepeatedCommands) {
  odonata::heartbeat_t hb{};
  hb.service = "odonata-plant";
  hb.instance = "plant-1";
  hb.state = "running";
  hb.skipped = 7;
  hb.repeated = 5;
  hb.gaps = 2;
  bus_->Publish(bus_->channels().heartbeat, hb);
  Pump(*bus_);
  const nlohmann::json s = node_->Summary();
  ASSERT_TRUE(s["services"].contains("plant-1")) << s.dump();
  EXPECT_EQ(s["services"]["plant-1"]["skipped"], 7);
  EXPECT_EQ(s["services"]["plant-1"]["repeated"], 5);
  EXPECT_EQ(s["services"]["plant-1"]["gaps"], 2);
}

// A flood of forged heartbeats and snapshots under ever new names: the monitor stays bounded and
// still knows the peer it heard last.
TEST_F(MonitorNodeTest, AFloodOfNewNamesKeepsTheMonitorBounded) {
  for (int i = 0; i < 600; ++i) {
    odonata::heartbeat_t hb{};
    hb.service = "forged";
    hb.instance = "peer-" + std::to_string(i);
    hb.state = "running";
    bus_->Publish(bus_->channels().heartbeat, hb);
    odonata::model_snapshot_t snap{};
    snap.instance = "ident-" + std::to_string(i);
    bus_->Publish(bus_->channels().model, snap);
    Pump(*bus_);
  }
  EXPECT_EQ(node_->peer_count(), MonitorNode::kMaxPeers);
  EXPECT_EQ(node_->snapshot_count(), MonitorNode::kMaxSnapshots);
  EXPECT_TRUE(node_->Summary()["services"].contains("peer-599"));
}

// The snapshot cache is bounded in bytes as well as in count: 16 forged 14 MB snapshots do not
// stay in memory together, the newest is kept, and each one forgotten is counted as dropped.
TEST_F(MonitorNodeTest, TheSnapshotCacheIsBoundedInBytes) {
  odonata::model_snapshot_t big{};
  big.num_outputs = 1;
  big.models.resize(1);
  auto& rules = big.models[0];
  rules.num_rules = 1;
  rules.output_widths = {1.0};
  rules.num_coefficients = 1;
  rules.coefficients = {{0.0}};
  rules.covariance_size = 14 << 17;  // 14 MB of doubles
  rules.covariances = {std::vector<double>(static_cast<std::size_t>(rules.covariance_size), 0.5)};
  rules.centres = {{}};
  rules.sigmas = {{}};
  rules.utility_sums = {0.0};
  rules.born = {0};
  big.outputs = {"y"};
  big.output_mean = {0.0};
  big.output_std = {1.0};
  big.output_lower = {-std::numeric_limits<double>::infinity()};
  big.output_upper = {std::numeric_limits<double>::infinity()};
  const auto dropped_before = bus_->stats().dropped;
  for (int i = 0; i < 16; ++i) {
    big.instance = "forged-" + std::to_string(i);
    bus_->Publish(bus_->channels().model, big);
    Pump(*bus_, 20);
  }
  EXPECT_LE(node_->snapshot_bytes(), MonitorNode::kMaxSnapshotBytes);
  EXPECT_LT(node_->snapshot_count(), 16u);
  EXPECT_GT(node_->snapshot_count(), 0u);
  EXPECT_GT(bus_->stats().dropped, dropped_before);
}

// Found by fuzzing: every new run stored a summary that held all earlier runs, so the summary
// doubled with each run (24 GB after a few thousand forged predictions). Now each run keeps its
// own scores, and only the latest kMaxFinishedRuns.
TEST_F(MonitorNodeTest, ManyRunsKeepTheSummaryBounded) {
  for (int run = 0; run < 200; ++run)
    for (int64_t k = 0; k < 3; ++k) Send(k, OneStep(k), FreeRun(k));
  const nlohmann::json s = node_->Summary();
  ASSERT_EQ(s["previous_runs"].size(), MonitorNode::kMaxFinishedRuns);
  for (const auto& r : s["previous_runs"]) EXPECT_FALSE(r.contains("previous_runs"));
  EXPECT_LT(s.dump().size(), 100000u);
}

// A rejected (NaN) prediction does not move the sample counter: the genuine one is scored.
TEST_F(MonitorNodeTest, ANanPredictionDoesNotShadowTheGenuineOne) {
  for (int64_t k = 0; k < 10; ++k) Send(k, OneStep(k), FreeRun(k));
  Send(10, std::nan(""), 0.0);
  Send(10, OneStep(10), FreeRun(10));
  const nlohmann::json s = node_->Summary();
  EXPECT_EQ(s["last_sample"], 10);
  EXPECT_EQ(s["outputs"]["roll_rad"]["one_step"]["samples"], 11);
  EXPECT_FALSE(s.contains("previous_runs"));
}

}  // namespace
}  // namespace odonata::monitor
