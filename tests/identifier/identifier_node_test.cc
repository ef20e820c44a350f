// IdentifierNode over memq://: pairing commands with states by seq, gaps reported and never
// bridged, several outputs over one regressor, every control command, and starting from a saved
// model. The test talks to the node through the node's own BusNode (memq delivers within one LCM
// instance) and turns the Asio loop itself.
#include "identifier_node.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "bus/model_snapshot_codec.hpp"
#include "support/memq_bus.hpp"

namespace odonata::identifier {
namespace {

void Pump(bus::BusNode& bus) { testing::Pump(bus, 2); }

IdentifierConfig Config() {
  IdentifierConfig c;
  c.instance = "id-test";
  c.spec.output_lags = 1;
  c.spec.input_lags = 1;
  c.spec.delay = 1;
  c.spec.outputs = {"roll_rad", "pitch_rad"};
  c.spec.inputs = {"u"};
  c.model.consequent = fuzzy::ConsequentKind::kSingleton;
  c.model.entropy.threshold = 0.05;
  c.ranges = {{"roll_rad", {-1.0, 1.0}}, {"pitch_rad", {-1.0, 1.0}}, {"u", {-1.0, 1.0}}};
  c.snapshot_period_s = 0;
  c.resume_wait_s = 0;
  return c;
}

double U(int64_t k) { return std::sin(0.05 * static_cast<double>(k)); }
double Roll(int64_t k) { return 0.5 * std::sin(0.05 * static_cast<double>(k) - 0.3); }
double Pitch(int64_t k) { return 0.3 * std::cos(0.07 * static_cast<double>(k)); }

class IdentifierNodeTest : public ::testing::Test {
 protected:
  void Start(std::optional<sysid::NarxModel> initial = std::nullopt) {
    bus_ = std::make_unique<bus::BusNode>(testing::MemqOptions("odonata-identifier"));
    bus_->Subscribe<odonata::prediction_t>(bus_->channels().prediction,
                                           [this](const auto& m) { predictions_.push_back(m); });
    bus_->Subscribe<odonata::model_snapshot_t>(bus_->channels().model,
                                               [this](const auto& m) { snapshots_.push_back(m); });
    node_ = std::make_unique<IdentifierNode>(*bus_, Config(), std::move(initial), "");
  }

  void SendCommand(int64_t k) {
    odonata::wing_command_t c{};
    c.seq = k;
    for (int w = 0; w < 4; ++w) c.freq_hz[w] = 5.4;
    c.num_excitations = 1;
    c.excitation_names = {"u"};
    c.excitations = {U(k)};
    c.source = "test";
    bus_->Publish(bus_->channels().command, c);
    Pump(*bus_);
  }
  void SendState(int64_t k) {
    odonata::plant_state_t s{};
    s.seq = k;
    s.command_seq = k - 1;
    s.attitude_rad[0] = Roll(k);
    s.attitude_rad[1] = Pitch(k);
    bus_->Publish(bus_->channels().state, s);
    Pump(*bus_);
  }
  // Samples [from, to): state k, then command k (answered by state k + 1).
  void Run(int64_t from, int64_t to, int64_t skip_state = -1) {
    for (int64_t k = from; k < to; ++k) {
      if (k != skip_state) SendState(k);
      SendCommand(k);
    }
  }
  void Control(int8_t command, double value = 0, const std::string& path = "") {
    odonata::control_t c{};
    c.target = "id-test";
    c.command = command;
    c.value = value;
    c.path = path;
    bus_->Publish(bus_->channels().control, c);
    Pump(*bus_);
  }

  std::unique_ptr<bus::BusNode> bus_;
  std::unique_ptr<IdentifierNode> node_;
  std::vector<odonata::prediction_t> predictions_;
  std::vector<odonata::model_snapshot_t> snapshots_;
};

TEST_F(IdentifierNodeTest, PredictsEveryOutputOfEverySampleFromOneRegressor) {
  Start();
  Run(0, 200);
  ASSERT_GE(predictions_.size(), 190u);
  for (std::size_t i = 0; i < predictions_.size(); ++i) {
    const auto& p = predictions_[i];
    ASSERT_EQ(p.num_outputs, 2);
    EXPECT_EQ(p.names, (std::vector<std::string>{"roll_rad", "pitch_rad"}));
    EXPECT_DOUBLE_EQ(p.measured[0], Roll(p.sample));
    EXPECT_DOUBLE_EQ(p.measured[1], Pitch(p.sample));
    if (i > 0) {
      EXPECT_EQ(p.sample, predictions_[i - 1].sample + 1);
    }
  }
  EXPECT_GE(node_->core().model().model(0).rules(), 1);
  EXPECT_GE(node_->core().model().model(1).rules(), 1);
  // Learning makes the last predictions good for both outputs.
  const auto& last = predictions_.back();
  EXPECT_NEAR(last.predicted[0], last.measured[0], 0.05);
  EXPECT_NEAR(last.predicted[1], last.measured[1], 0.05);
}

TEST_F(IdentifierNodeTest, AMissingStateIsReportedAsAGapAndNeverBridged) {
  Start();
  Run(0, 60, /*skip_state=*/30);
  EXPECT_GE(bus_->stats().gaps, 1);
  for (const auto& p : predictions_) {
    // Sample 30 is unknown, and sample 31's regressor would need y(30): neither is scored.
    EXPECT_NE(p.sample, 30);
    EXPECT_NE(p.sample, 31);
  }
  ASSERT_FALSE(predictions_.empty());
  EXPECT_EQ(predictions_.back().sample, 58);  // sample 59 needs state 60
}

TEST_F(IdentifierNodeTest, AStateWithoutItsCommandWaitsAndTheCommandCompletesIt) {
  Start();
  SendState(0);
  SendCommand(0);
  SendState(1);
  SendState(2);  // command 1 arrives late (out of order on the wire)
  SendCommand(1);
  SendCommand(2);
  SendState(3);
  std::vector<int64_t> samples;
  for (const auto& p : predictions_) samples.push_back(p.sample);
  EXPECT_EQ(samples, (std::vector<int64_t>{1, 2}));  // y(1) from [y(0), u(0)], y(2) likewise
}

TEST_F(IdentifierNodeTest, EveryControlCommandActs) {
  Start();
  Run(0, 100);
  const int64_t learned = node_->core().samples_learned();
  ASSERT_GT(learned, 0);

  Control(odonata::control_t::FREEZE);
  predictions_.clear();
  Run(100, 150);
  EXPECT_EQ(node_->core().samples_learned(), learned);
  ASSERT_FALSE(predictions_.empty());
  for (const auto& p : predictions_) EXPECT_EQ(p.learning, 0);

  Control(odonata::control_t::RESUME);
  Run(150, 160);
  EXPECT_GT(node_->core().samples_learned(), learned);

  Control(odonata::control_t::SET_ENTROPY_THRESHOLD, 0.3);
  EXPECT_DOUBLE_EQ(node_->core().model().model(0).config().entropy.threshold, 0.3);
  const int64_t dropped = bus_->stats().dropped + bus_->stats().decode_errors;
  Control(odonata::control_t::SET_ENTROPY_THRESHOLD, 7.0);  // out of range: counted, ignored
  EXPECT_DOUBLE_EQ(node_->core().model().model(0).config().entropy.threshold, 0.3);
  EXPECT_GT(bus_->stats().dropped + bus_->stats().decode_errors, dropped);

  Control(odonata::control_t::SET_FORGETTING, 0.98);
  EXPECT_DOUBLE_EQ(node_->core().model().model(0).config().forgetting, 0.98);
  Control(odonata::control_t::SET_FORGETTING, 1.5);  // out of range: refused by the core
  EXPECT_DOUBLE_EQ(node_->core().model().model(0).config().forgetting, 0.98);

  snapshots_.clear();
  Control(odonata::control_t::PUBLISH_SNAPSHOT);
  ASSERT_EQ(snapshots_.size(), 1u);
  const sysid::NarxModel from_bus = bus::DecodeSnapshot(snapshots_[0]);
  // Everything, the forgetting factor and the pruning bookkeeping included.
  EXPECT_EQ(from_bus.ToJson(), node_->core().model().ToJson());

  char path[] = "/tmp/odonata_identifier_node_XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  close(fd);
  Control(odonata::control_t::SAVE_MODEL, 0, path);
  const sysid::NarxModel saved = sysid::NarxModel::Load(path);
  EXPECT_EQ(saved.ToJson(), node_->core().model().ToJson());
  std::remove(path);

  Control(odonata::control_t::RESET);
  EXPECT_EQ(node_->core().model().total_rules(), 0);

  Control(odonata::control_t::SHUTDOWN);
  EXPECT_TRUE(bus_->io().stopped());
}

TEST_F(IdentifierNodeTest, StartsFromASavedModelAndLearnsOnFromIt) {
  Start();
  Run(0, 120);
  const sysid::NarxModel trained = node_->core().model();
  predictions_.clear();
  node_.reset();
  bus_.reset();

  Start(trained);
  EXPECT_EQ(node_->core().model().ToJson(), trained.ToJson());
  Control(odonata::control_t::FREEZE);
  Run(120, 140);
  ASSERT_FALSE(predictions_.empty());
  // Its first prediction is the saved model's, not an empty model's.
  const auto& p = predictions_.front();
  Eigen::VectorXd x(3);
  x << Roll(p.sample - 1), Pitch(p.sample - 1), U(p.sample - 1);
  const Eigen::VectorXd expected = trained.Predict(x);
  EXPECT_DOUBLE_EQ(p.predicted[0], expected(0));
  EXPECT_DOUBLE_EQ(p.predicted[1], expected(1));
}

TEST(IdentifierConfig, WithoutAFileTheRollLoopIsIdentified) {
  const IdentifierConfig c = DefaultIdentifierConfig();
  EXPECT_EQ(c.spec.outputs, std::vector<std::string>{"roll_rad"});
  EXPECT_EQ(c.spec.inputs, std::vector<std::string>{"u_roll_rad"});
  EXPECT_EQ(c.ranges.count("roll_rad"), 1u);
  EXPECT_EQ(c.channels.state, "DIMAV_STATE");
}

}  // namespace
}  // namespace odonata::identifier
