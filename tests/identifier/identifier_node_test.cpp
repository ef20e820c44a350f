// IdentifierNode over memq://: pairing commands with states by seq, gaps reported and never
// bridged, several outputs over one regressor, every control command, and starting from a saved
// model. The test talks to the node through the node's own BusNode (memq delivers within one LCM
// instance) and turns the Asio loop itself.
#include "identifier_node.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model_messages/model_snapshot_message.hpp"
#include "odonata/control_reply_t.hpp"
#include "odonata/heartbeat_t.hpp"
#include "odonata/signals_t.hpp"
#include "support/memq_bus.hpp"

namespace odonata::identifier {
namespace {

void Pump(bus::BusNode& bus) { testing::Pump(bus, 2); }

IdentifierConfig Config() {
  IdentifierConfig c;
  c.instance = "id-test";
  c.snapshot_every_samples = 0;  // the tests count the snapshots they ask for
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
// Beat state k's roll average, and the applied roll command of sample k (in beat state k + 1).
double RollAvg(int64_t k) { return 0.4 * std::sin(0.05 * static_cast<double>(k) - 0.5); }
double Applied(int64_t k) { return 0.8 * std::sin(0.09 * static_cast<double>(k) + 0.2); }

// Outputs from the beat averages and the state, the input from the applied command.
IdentifierConfig BeatConfig() {
  IdentifierConfig c = Config();
  c.spec.outputs = {"roll_rad_avg", "pitch_rad"};
  c.spec.inputs = {"u_roll_applied_rad"};
  c.ranges = {{"roll_rad_avg", {-1.0, 1.0}},
              {"pitch_rad", {-1.0, 1.0}},
              {"u_roll_applied_rad", {-1.0, 1.0}}};
  return c;
}

class IdentifierNodeTest : public ::testing::Test {
 protected:
  void Start(std::optional<sysid::NarxModel> initial = std::nullopt,
             const IdentifierConfig& config = Config()) {
    bus::BusOptions options = testing::MemqOptions("odonata-identifier");
    options.instance = config.instance;  // as odonata-identifier's main sets it
    bus_ = std::make_unique<bus::BusNode>(options);
    bus_->Subscribe<odonata::prediction_t>(bus_->channels().prediction,
                                           [this](const auto& m) { predictions_.push_back(m); });
    bus_->Subscribe<odonata::model_snapshot_t>(bus_->channels().model,
                                               [this](const auto& m) { snapshots_.push_back(m); });
    node_ = std::make_unique<IdentifierNode>(*bus_, config, std::move(initial), "", models_dir_);
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
  // Beat state k: published by the plant right after state k.
  void SendBeat(int64_t k) {
    odonata::beat_state_t b{};
    b.seq = k;
    b.command_seq = k - 1;
    b.attitude_rad[0] = RollAvg(k);
    b.u_roll_applied_rad = Applied(k - 1);  // the command applied over [t_k-1, t_k)
    bus_->Publish(bus_->channels().beat_state, b);
    Pump(*bus_);
  }
  // Samples [from, to): state k (and beat state k), then command k (answered by state k + 1).
  void Run(int64_t from, int64_t to, int64_t skip_state = -1, bool beats = false,
           int64_t skip_beat = -1) {
    for (int64_t k = from; k < to; ++k) {
      if (k != skip_state) SendState(k);
      if (beats && k != skip_beat) SendBeat(k);
      SendCommand(k);
    }
  }
  std::vector<int64_t> Samples() const {
    std::vector<int64_t> samples;
    for (const auto& p : predictions_) samples.push_back(p.sample);
    return samples;
  }
  void Control(int8_t command, double value = 0, const std::string& path = "",
               const std::string& sender = "odonata-control", int64_t utime = 0) {
    odonata::control_t c{};
    c.utime = utime;
    c.sender = sender;
    c.target = "id-test";
    c.command = command;
    c.value = value;
    c.path = path;
    bus_->Publish(bus_->channels().control, c);
    Pump(*bus_);
  }

  void SetUp() override {
    char tmpl[] = "/tmp/odonata_identifier_models_XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    models_dir_ = tmpl;
  }
  void TearDown() override {
    node_.reset();
    bus_.reset();
    std::filesystem::remove_all(models_dir_);
  }

  std::string models_dir_;
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

TEST_F(IdentifierNodeTest, AMissingStateIsAGapThatIsBridged) {
  Start();
  // The states after it wait for its resend (a lockstep window) until more than
  // kMaxStatesAfterHole of them are held: then the hole is given up.
  Run(0, 80, /*skip_state=*/30);
  EXPECT_GE(bus_->stats().gaps, 1);
  // Sample 30 is unknown: it is learned as the line between its neighbours (max_gap, as
  // odonata-fit bridges a missing row) but never scored; sample 31's regressor takes that y(30),
  // so the history goes on without a warm-up.
  EXPECT_GE(node_->core().bridged(), 1);
  EXPECT_EQ(std::count_if(predictions_.begin(), predictions_.end(),
                          [](const auto& p) { return p.sample == 30; }),
            0);
  EXPECT_EQ(std::count_if(predictions_.begin(), predictions_.end(),
                          [](const auto& p) { return p.sample == 31; }),
            1);
  ASSERT_FALSE(predictions_.empty());
  EXPECT_EQ(predictions_.back().sample, 78);  // sample 79 needs state 80
}

TEST_F(IdentifierNodeTest, WithoutBridgingAMissingStateRestartsTheHistory) {
  IdentifierConfig c = Config();
  c.max_gap = 0;
  Start(std::nullopt, c);
  Run(0, 80, /*skip_state=*/30);
  EXPECT_GE(bus_->stats().gaps, 1);
  EXPECT_EQ(node_->core().bridged(), 0);
  for (const auto& p : predictions_) {
    // Sample 30 is unknown, and sample 31's regressor would need y(30): neither is scored.
    EXPECT_NE(p.sample, 30);
    EXPECT_NE(p.sample, 31);
  }
  ASSERT_FALSE(predictions_.empty());
  EXPECT_EQ(predictions_.back().sample, 78);
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
  const sysid::NarxModel from_bus = model_messages::DecodeSnapshot(snapshots_[0]);
  // Everything, the forgetting factor and the pruning bookkeeping included.
  EXPECT_EQ(from_bus.ToJson(), node_->core().model().ToJson());

  // A name from the bus is written inside the models directory, and only a plain name is.
  Control(odonata::control_t::SAVE_MODEL, 0, "saved.json");
  const sysid::NarxModel saved = sysid::NarxModel::Load(models_dir_ + "/saved.json");
  EXPECT_EQ(saved.ToJson(), node_->core().model().ToJson());
  const std::string outside = models_dir_ + "-outside.json";
  const int64_t before_refusals = bus_->stats().dropped;
  for (const std::string& bad : {outside, std::string("../x.json"), std::string("sub/x.json"),
                                 std::string(".hidden"), std::string("a b.json")}) {
    Control(odonata::control_t::SAVE_MODEL, 0, bad);
  }
  EXPECT_EQ(bus_->stats().dropped, before_refusals + 5);
  EXPECT_FALSE(std::filesystem::exists(outside));
  EXPECT_FALSE(
      std::filesystem::exists(std::filesystem::path(models_dir_).parent_path() / "x.json"));
  // A symlink planted under the name is replaced, never written through.
  const std::string victim = models_dir_ + "-victim.txt";
  std::ofstream(victim) << "precious";
  std::filesystem::create_symlink(victim, models_dir_ + "/link.json");
  Control(odonata::control_t::SAVE_MODEL, 0, "link.json");
  EXPECT_FALSE(std::filesystem::is_symlink(models_dir_ + "/link.json"));
  std::ifstream victim_in(victim);
  std::string victim_text;
  victim_in >> victim_text;
  EXPECT_EQ(victim_text, "precious");
  std::filesystem::remove(victim);
  // A name that is already a file other than a saved model (the run's live event log, its
  // configuration) is refused: the models directory may be the run's folder (issue 24 point 4).
  std::ofstream(models_dir_ + "/odonata.lcmlog.00000") << "LCM events";
  const int64_t before_log = bus_->stats().dropped;
  Control(odonata::control_t::SAVE_MODEL, 0, "odonata.lcmlog.00000");
  EXPECT_EQ(bus_->stats().dropped, before_log + 1);
  std::ifstream log_in(models_dir_ + "/odonata.lcmlog.00000");
  std::string log_text;
  std::getline(log_in, log_text);
  EXPECT_EQ(log_text, "LCM events");
  Control(odonata::control_t::SAVE_MODEL, 0, "saved.json");  // a saved model may be replaced
  EXPECT_EQ(bus_->stats().dropped, before_log + 1);
  // A models directory of its own is made at the first named save (odonata-run's models/).
  std::filesystem::remove_all(models_dir_);
  Control(odonata::control_t::SAVE_MODEL, 0, "fresh.json");
  EXPECT_TRUE(std::filesystem::is_regular_file(models_dir_ + "/fresh.json"));

  // Reset and shutdown only from allowed senders.
  const int rules = node_->core().model().total_rules();
  ASSERT_GT(rules, 0);
  Control(odonata::control_t::RESET, 0, "", "intruder");
  Control(odonata::control_t::SHUTDOWN, 0, "", "");
  EXPECT_EQ(node_->core().model().total_rules(), rules);
  EXPECT_FALSE(bus_->io().stopped());
  Control(odonata::control_t::RESET);
  EXPECT_EQ(node_->core().model().total_rules(), 0);

  Control(odonata::control_t::SHUTDOWN);
  EXPECT_TRUE(bus_->io().stopped());
}

// Every command addressed to the identifier is answered on ODONATA_CONTROL_REPLY, matched to
// its request by sender and seq: accepted with the value now in force, or rejected with why.
// Freeze and save-model before anything was learned (issue 48's first-hour papercuts): the
// freeze is obeyed and says the model is empty; save-model is refused with why, no file written.
TEST_F(IdentifierNodeTest, AnEmptyModelIsSaidSoOnFreezeAndNotSaved) {
  Start();
  std::vector<odonata::control_reply_t> replies;
  bus_->Subscribe<odonata::control_reply_t>(bus_->channels().control_reply,
                                            [&](const auto& r) { replies.push_back(r); });
  Control(odonata::control_t::FREEZE);
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_TRUE(replies[0].accepted);
  EXPECT_NE(replies[0].reason.find("empty model"), std::string::npos) << replies[0].reason;
  replies.clear();
  Control(odonata::control_t::SAVE_MODEL, 0, "empty.json");
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_FALSE(replies[0].accepted);
  EXPECT_NE(replies[0].reason.find("nothing to save"), std::string::npos) << replies[0].reason;
  EXPECT_FALSE(std::filesystem::exists(models_dir_ + "/empty.json"));
  // Once it has learned, both are as before.
  Control(odonata::control_t::RESUME);
  Run(0, 50);
  replies.clear();
  Control(odonata::control_t::FREEZE);
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_EQ(replies[0].reason, "frozen: predicting, not learning");
  Control(odonata::control_t::SAVE_MODEL, 0, "learned.json");
  EXPECT_TRUE(std::filesystem::is_regular_file(models_dir_ + "/learned.json"));
}

TEST_F(IdentifierNodeTest, EveryCommandIsAnsweredWithTheValueInForce) {
  Start();
  std::vector<odonata::control_reply_t> replies;
  bus_->Subscribe<odonata::control_reply_t>(bus_->channels().control_reply,
                                            [&](const auto& r) { replies.push_back(r); });
  Run(0, 50);
  int64_t seq = 1000;
  const auto ask = [&](int8_t command, double value, const std::string& sender,
                       const std::string& target) -> const odonata::control_reply_t* {
    replies.clear();
    odonata::control_t c{};
    c.seq = ++seq;
    c.sender = sender;
    c.target = target;
    c.command = command;
    c.value = value;
    bus_->Publish(bus_->channels().control, c);
    Pump(*bus_);
    if (replies.empty()) return nullptr;
    EXPECT_EQ(replies.size(), 1u);
    EXPECT_EQ(replies[0].request_seq, seq);
    EXPECT_EQ(replies[0].request_sender, sender);
    EXPECT_EQ(replies[0].command, command);
    EXPECT_EQ(replies[0].instance, "id-test");
    return &replies[0];
  };
  const auto param = [](const odonata::control_reply_t& r, const std::string& name) {
    for (int i = 0; i < r.num_params; ++i)
      if (r.names[static_cast<std::size_t>(i)] == name)
        return r.values[static_cast<std::size_t>(i)];
    ADD_FAILURE() << "no parameter " << name;
    return std::nan("");
  };

  auto* r = ask(odonata::control_t::SET_ENTROPY_THRESHOLD, 0.3, "odonata-control", "id-test");
  ASSERT_NE(r, nullptr);
  EXPECT_TRUE(r->accepted) << r->reason;
  EXPECT_DOUBLE_EQ(param(*r, "entropy_threshold"), 0.3);

  r = ask(odonata::control_t::SET_ENTROPY_THRESHOLD, 7.0, "odonata-control", "odonata-identifier");
  ASSERT_NE(r, nullptr);
  EXPECT_FALSE(r->accepted);
  EXPECT_NE(r->reason.find("threshold"), std::string::npos) << r->reason;
  EXPECT_DOUBLE_EQ(param(*r, "entropy_threshold"), 0.3);  // unchanged, and says so

  r = ask(odonata::control_t::GET, 0, "odonata-control", "");  // to every service
  ASSERT_NE(r, nullptr);
  EXPECT_TRUE(r->accepted);
  EXPECT_EQ(param(*r, "samples_learned"), static_cast<double>(node_->core().samples_learned()));
  EXPECT_EQ(param(*r, "rules"), node_->core().model().total_rules());
  EXPECT_EQ(param(*r, "learning"), 1.0);
  EXPECT_EQ(param(*r, "forgetting"), 1.0);
  // Whether the model has seen enough (SettlingWatch), per output, in words and as a number: 50
  // samples are too few for any regime to have been visited kRegimeSamples times.
  EXPECT_NE(r->reason.find("seen enough? "), std::string::npos) << r->reason;
  EXPECT_NE(r->reason.find("short of excitation"), std::string::npos) << r->reason;
  for (const auto& o : node_->core().model().spec().outputs)
    EXPECT_EQ(param(*r, "seen_enough." + o), 0.0) << o;

  r = ask(odonata::control_t::FREEZE, 0, "odonata-control", "id-test");
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(param(*r, "learning"), 0.0);

  r = ask(odonata::control_t::SAVE_MODEL, 0, "odonata-control", "id-test");  // no --save-model
  ASSERT_NE(r, nullptr);
  EXPECT_FALSE(r->accepted);

  r = ask(odonata::control_t::RESET, 0, "intruder", "id-test");  // not an allowed sender
  ASSERT_NE(r, nullptr);
  EXPECT_FALSE(r->accepted);
  EXPECT_NE(r->reason.find("intruder"), std::string::npos) << r->reason;
  EXPECT_GT(node_->core().model().total_rules(), 0);
  // Freeze, resume and save-model are gated alike (issue 24 point 4): a forged freeze mid-run
  // stopped learning at 1009 of 2997 samples.
  for (const int8_t gated :
       {odonata::control_t::RESUME, odonata::control_t::FREEZE, odonata::control_t::SAVE_MODEL}) {
    r = ask(gated, 0, "intruder", "id-test");
    ASSERT_NE(r, nullptr);
    EXPECT_FALSE(r->accepted) << int(gated);
    EXPECT_NE(r->reason.find("not among the allowed senders"), std::string::npos) << r->reason;
  }
  EXPECT_FALSE(node_->core().learning());  // still frozen: the forged resume did nothing

  EXPECT_EQ(ask(odonata::control_t::GET, 0, "odonata-control", "someone-else"), nullptr);

  // Shutdown answers, then stops: a stopped node delivers nothing more over memq, so the answer
  // itself is checked over udpm (tests/integration/control_test.sh).
  ask(odonata::control_t::SHUTDOWN, 0, "odonata-control", "id-test");
  EXPECT_TRUE(bus_->io().stopped());
}

TEST_F(IdentifierNodeTest, ASavedModelKeepsEachRulesCovarianceOnTheSamplesItKept) {
  // Issue 60 point 2, online: SAVE_MODEL writes each rule's parameter covariance, estimated on the
  // samples kept for the refits, beside the model, for odonata-export's local models.
  IdentifierConfig c = Config();
  c.model.consequent = fuzzy::ConsequentKind::kLinear;
  Start(std::nullopt, c);
  Run(0, 300);
  Control(odonata::control_t::SAVE_MODEL, 0, "linear.json");
  const auto cov = sysid::NarxModel::SavedLocalCovariance(models_dir_ + "/linear.json");
  ASSERT_TRUE(cov.is_object()) << cov.dump();
  for (const auto& out : c.spec.outputs) {
    const auto& model = node_->core().model();
    const int o = out == "roll_rad" ? 0 : 1;
    ASSERT_EQ(cov[out].size(), static_cast<std::size_t>(model.model(o).rules())) << out;
    int with = 0;
    for (const auto& rule : cov[out]) {
      if (rule.is_null()) continue;
      EXPECT_EQ(rule.size(), 4u) << out;  // [1, roll, pitch, u]
      ++with;
    }
    EXPECT_GT(with, 0) << out;
  }
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

// A restarted identifier resumes only a snapshot of its own signals and within its own bounds,
// with the snapshot's learned-sample count and its frozen state; any other starts it fresh.
// Replaying a recorded flight (lcm-logplayer keeps each message's utime) must not freeze a live
// identifier with the flight's own freeze (issue 23 point 6).
TEST_F(IdentifierNodeTest, IgnoresAControlMessagePublishedLongBeforeItStarted) {
  Start();
  const int64_t an_hour_ago = bus::NowUtime() - 3'600'000'000;
  Control(odonata::control_t::FREEZE, 0, "", "odonata-control", an_hour_ago);
  EXPECT_TRUE(node_->core().learning()) << "a replayed freeze was obeyed";
  EXPECT_EQ(bus_->stats().dropped, 1);
  EXPECT_NE(bus_->stats().last_error.find("before this service started"), std::string::npos)
      << bus_->stats().last_error;
  Control(odonata::control_t::FREEZE, 0, "", "odonata-control", bus::NowUtime());
  EXPECT_FALSE(node_->core().learning()) << "a live freeze was not obeyed";
}

TEST_F(IdentifierNodeTest, ResumesOnlyAFittingSnapshotWithItsCountAndFrozenState) {
  Start();
  Run(0, 120);
  Control(odonata::control_t::FREEZE);
  snapshots_.clear();
  Control(odonata::control_t::PUBLISH_SNAPSHOT);
  ASSERT_EQ(snapshots_.size(), 1u);
  const odonata::model_snapshot_t snap = snapshots_[0];
  const int64_t learned = node_->core().samples_learned();
  ASSERT_GT(learned, 100);
  EXPECT_EQ(snap.samples_learned, learned);
  EXPECT_EQ(snap.learning, 0);
  const nlohmann::json model = node_->core().model().ToJson();

  const auto resume_with = [&](IdentifierConfig config, const odonata::model_snapshot_t& s) {
    node_.reset();
    bus_.reset();
    config.resume_wait_s = 30;  // waits for the snapshot
    Start(std::nullopt, config);
    bus_->Publish(bus_->channels().model, s);
    Pump(*bus_);
  };
  resume_with(Config(), snap);
  EXPECT_EQ(node_->core().model().ToJson(), model);
  EXPECT_EQ(node_->core().samples_learned(), learned);
  EXPECT_FALSE(node_->core().learning());

  IdentifierConfig pitch_only = Config();  // another experiment under the same instance name
  pitch_only.spec.outputs = {"pitch_rad"};
  resume_with(pitch_only, snap);
  EXPECT_EQ(node_->core().model().total_rules(), 0);
  EXPECT_EQ(node_->core().samples_learned(), 0);
  EXPECT_TRUE(node_->core().learning());
  EXPECT_EQ(bus_->stats().dropped, 1);
  EXPECT_NE(bus_->stats().last_error.find("not [pitch_rad]"), std::string::npos)
      << bus_->stats().last_error;

  odonata::model_snapshot_t huge = snap;  // claims a cap far beyond this identifier's
  huge.models[0].max_rules = 1 << 30;
  resume_with(Config(), huge);
  EXPECT_EQ(node_->core().model().total_rules(), 0);
  EXPECT_NE(bus_->stats().last_error.find("cap"), std::string::npos) << bus_->stats().last_error;

  odonata::model_snapshot_t bad_scaling = snap;
  bad_scaling.regressor_half[0] = 0.0;
  resume_with(Config(), bad_scaling);
  EXPECT_EQ(node_->core().model().total_rules(), 0);
  EXPECT_NE(bus_->stats().last_error.find("scaling"), std::string::npos)
      << bus_->stats().last_error;
}

// Traffic of the run replayed into an identifier that resumed from a snapshot (a capture sent
// again after a restart, or resends) teaches it nothing twice; the samples it missed while down
// are gaps; a new run of the plant is learned from its start.
TEST_F(IdentifierNodeTest, AResumedIdentifierLearnsNoSampleItHeldAndCountsThoseItMissed) {
  Start();
  Run(0, 120);
  snapshots_.clear();
  Control(odonata::control_t::PUBLISH_SNAPSHOT);
  ASSERT_EQ(snapshots_.size(), 1u);
  const odonata::model_snapshot_t snap = snapshots_[0];
  EXPECT_EQ(snap.learned_through, 118);  // state 119 completed sample 118
  const nlohmann::json model = node_->core().model().ToJson();
  const int64_t learned = node_->core().samples_learned();

  node_.reset();
  bus_.reset();
  predictions_.clear();
  IdentifierConfig config = Config();
  config.resume_wait_s = 30;
  Start(std::nullopt, config);
  bus_->Publish(bus_->channels().model, snap);
  Pump(*bus_);
  ASSERT_EQ(node_->core().samples_learned(), learned);
  Run(60, 120);  // the run's own traffic again
  EXPECT_EQ(node_->core().samples_learned(), learned);
  EXPECT_EQ(node_->core().model().ToJson(), model);
  EXPECT_TRUE(predictions_.empty());
  EXPECT_EQ(node_->core().already_learned(), 59);  // samples 60 … 118
  EXPECT_NE(bus_->stats().last_error.find("already learned"), std::string::npos)
      << bus_->stats().last_error;
  EXPECT_EQ(node_->core().gaps(), 0);

  Run(130, 200);  // the run goes on: samples 119 … 129 were missed while it was down
  EXPECT_EQ(node_->core().gaps(), 11);
  EXPECT_GE(bus_->stats().gaps, 11);
  // Samples 130 … 198, but the first only fills the history (one lag).
  EXPECT_EQ(node_->core().samples_learned(), learned + 68);
  EXPECT_EQ(node_->core().learned_through(), 198);

  const int64_t before_new_run = node_->core().samples_learned();
  Run(0, 50);  // the plant starts a new run: its samples are new, whatever their indices
  EXPECT_EQ(node_->core().samples_learned(), before_new_run + 48);  // 0 … 48, less the first
}

TEST_F(IdentifierNodeTest, BeatAveragesComeFromBeatStateKAndTheAppliedCommandFromBeatStateKPlus1) {
  Start(std::nullopt, BeatConfig());
  Run(0, 120, -1, /*beats=*/true);
  ASSERT_GE(predictions_.size(), 110u);
  for (const auto& p : predictions_) {
    EXPECT_DOUBLE_EQ(p.measured[0], RollAvg(p.sample));
    EXPECT_DOUBLE_EQ(p.measured[1], Pitch(p.sample));
  }
  const sysid::NarxModel trained = node_->core().model();
  predictions_.clear();
  node_.reset();
  bus_.reset();

  // A frozen copy predicts y(k) from y(k-1) and u(k-1), the command applied over [t_k-1, t_k),
  // which beat state k carries.
  Start(trained, BeatConfig());
  Control(odonata::control_t::FREEZE);
  Run(120, 140, -1, true);
  ASSERT_FALSE(predictions_.empty());
  for (const auto& p : predictions_) {
    Eigen::VectorXd x(3);
    x << RollAvg(p.sample - 1), Pitch(p.sample - 1), Applied(p.sample - 1);
    const Eigen::VectorXd expected = trained.Predict(x);
    EXPECT_DOUBLE_EQ(p.predicted[0], expected(0));
    EXPECT_DOUBLE_EQ(p.predicted[1], expected(1));
  }
}

TEST_F(IdentifierNodeTest, AMissingBeatStateIsAGapThatIsBridged) {
  Start(std::nullopt, BeatConfig());
  Run(0, 160, -1, /*beats=*/true, /*skip_beat=*/30);
  EXPECT_GE(bus_->stats().gaps, 2);
  EXPECT_EQ(node_->core().bridged(), 2);
  const auto samples = Samples();
  // Sample 29 lacks its applied command and sample 30 its averages: both are bridged, neither is
  // scored; sample 31's regressor takes the bridged y(30), and every other sample is scored.
  for (int64_t k : {29, 30}) EXPECT_EQ(std::count(samples.begin(), samples.end(), k), 0);
  for (int64_t k : {28, 31, 32}) EXPECT_EQ(std::count(samples.begin(), samples.end(), k), 1);
  EXPECT_EQ(samples.back(), 158);  // sample 159 needs state 160
}

TEST_F(IdentifierNodeTest, WithoutBridgingAMissingBeatStateRestartsTheHistory) {
  IdentifierConfig c = BeatConfig();
  c.max_gap = 0;
  Start(std::nullopt, c);
  Run(0, 160, -1, /*beats=*/true, /*skip_beat=*/30);
  EXPECT_GE(bus_->stats().gaps, 2);
  const auto samples = Samples();
  // Sample 31's regressor would need y(30): none of 29, 30, 31 is scored; every other sample is.
  for (int64_t k : {29, 30, 31}) EXPECT_EQ(std::count(samples.begin(), samples.end(), k), 0);
  EXPECT_EQ(std::count(samples.begin(), samples.end(), 28), 1);
  EXPECT_EQ(std::count(samples.begin(), samples.end(), 32), 1);
  EXPECT_EQ(samples.back(), 158);
}

TEST_F(IdentifierNodeTest, WithoutBeatSignalsBeatStatesAreIgnored) {
  Start();
  Run(0, 60, -1, /*beats=*/true, /*skip_beat=*/30);
  EXPECT_EQ(bus_->stats().gaps, 0);
  EXPECT_EQ(Samples().size(), 58u);  // 1 … 58
}

TEST(IdentifierConfig, WithoutAFileTheRollLoopIsIdentified) {
  const IdentifierConfig c = DefaultIdentifierConfig();
  EXPECT_EQ(c.spec.outputs, std::vector<std::string>{"roll_rad"});
  EXPECT_EQ(c.spec.inputs, std::vector<std::string>{"u_roll_applied_rad"});  // open loop
  EXPECT_EQ(c.ranges.count("roll_rad"), 1u);
  EXPECT_EQ(c.ranges.count("u_roll_applied_rad"), 1u);
  EXPECT_EQ(c.channels.state, "DIMAV_STATE");
  EXPECT_EQ(c.channels.beat_state, "DIMAV_BEAT_STATE");
}

// A configuration that names a signal the vehicle does not send is an error the identifier says
// on its heartbeat and in GET's answer (rejected, with the names the vehicle has), not a quiet
// "accepted" with nothing learned (issue 23 point 7); once the names match, it runs again.
// Issue 51 point 1: a prediction that is not finite (here inputs 1e300, finite but far beyond any
// range) is never published: the identifier says so on its heartbeat, keeps the exit code of a
// run that diverged, restores the last good model and goes on predicting.
TEST_F(IdentifierNodeTest, ANonFinitePredictionRestoresTheLastGoodModelAndIsAnError) {
  IdentifierConfig c = Config();
  c.source = SampleSource::kSignals;
  c.spec.outputs = {"vz"};
  c.spec.inputs = {"throttle"};
  c.ranges = {{"vz", {-1.0, 1.0}}, {"throttle", {0.0, 1.0}}};
  c.snapshot_every_samples = 50;
  Start(std::nullopt, c);
  std::vector<std::string> states;
  bus_->Subscribe<odonata::heartbeat_t>(bus_->channels().heartbeat,
                                        [&](const auto& h) { states.push_back(h.state); });
  std::vector<odonata::prediction_t> predictions;
  bus_->Subscribe<odonata::prediction_t>(bus_->channels().prediction,
                                         [&](const auto& p) { predictions.push_back(p); });
  const auto send = [&](int64_t k, double throttle) {
    odonata::signals_t m{};
    m.seq = k;
    m.source = "veh";
    m.num_signals = 2;
    m.names = {"vz", "throttle"};
    m.values = {0.5 * std::sin(0.05 * double(k)), throttle};
    bus_->Publish(bus_->channels().signals, m);
    Pump(*bus_);
  };
  for (int64_t k = 0; k < 120; ++k) send(k, 0.5 + 0.4 * std::sin(0.3 * double(k)));
  send(120, 1e300);  // applied from 120 on: it reaches the prediction of sample 121
  const std::size_t before = predictions.size();
  ASSERT_GT(before, 100u);
  send(121, 0.5);
  EXPECT_EQ(predictions.size(), before) << "the non-finite prediction was published";
  ASSERT_FALSE(states.empty());
  EXPECT_NE(states.back().find("error: a prediction was not finite at sample 121"),
            std::string::npos)
      << states.back();
  EXPECT_EQ(bus_->exit_code(), kExitDiverged);
  EXPECT_EQ(node_->core().samples_learned(), 100) << "the snapshot at 100 learned samples is back";
  EXPECT_TRUE(node_->core().model().Readable());
  for (int64_t k = 122; k < 130; ++k) send(k, 0.5);
  EXPECT_GT(predictions.size(), before) << "it predicts again";
  for (const auto& p : predictions) EXPECT_TRUE(std::isfinite(p.predicted[0]));
  // A SHUTDOWN afterwards (as SIGTERM, Stop(0)) leaves the exit code the divergence set (issue 61).
  Control(odonata::control_t::SHUTDOWN);
  EXPECT_EQ(bus_->exit_code(), kExitDiverged);
}

TEST_F(IdentifierNodeTest, ASignalNameTheVehicleDoesNotSendIsReportedNotSilent) {
  IdentifierConfig c = Config();
  c.source = SampleSource::kSignals;
  c.spec.outputs = {"vz"};
  c.spec.inputs = {"throttle"};
  c.ranges = {{"vz", {-1.0, 1.0}}, {"throttle", {0.0, 1.0}}};
  Start(std::nullopt, c);
  std::vector<std::string> states;
  bus_->Subscribe<odonata::heartbeat_t>(bus_->channels().heartbeat,
                                        [&](const auto& h) { states.push_back(h.state); });
  std::vector<odonata::control_reply_t> replies;
  bus_->Subscribe<odonata::control_reply_t>(bus_->channels().control_reply,
                                            [&](const auto& r) { replies.push_back(r); });
  const auto send = [&](int64_t k, const std::string& output_name) {
    odonata::signals_t m{};
    m.seq = k;
    m.source = "veh";
    m.num_signals = 2;
    m.names = {output_name, "throttle"};
    m.values = {0.1 * std::sin(0.1 * double(k)), 0.5};
    bus_->Publish(bus_->channels().signals, m);
    Pump(*bus_);
  };
  int64_t seq = 0;
  const auto get = [&]() {
    replies.clear();
    odonata::control_t q{};
    q.seq = ++seq;  // a new request, not a resend of the last one
    q.sender = "odonata-control";
    q.target = "id-test";
    q.command = odonata::control_t::GET;
    bus_->Publish(bus_->channels().control, q);
    Pump(*bus_);
    EXPECT_EQ(replies.size(), 1u);
    return replies.empty() ? odonata::control_reply_t{} : replies.back();
  };
  for (int64_t k = 0; k < 5; ++k) send(k, "vz_mps");
  ASSERT_FALSE(states.empty());
  EXPECT_NE(states.back().find("refusing input"), std::string::npos) << states.back();
  EXPECT_NE(states.back().find("have no 'vz' (they have vz_mps, throttle)"), std::string::npos)
      << states.back();
  const auto refused = get();
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.reason.find("input refused (5 messages)"), std::string::npos) << refused.reason;
  EXPECT_TRUE(Samples().empty());
  for (int64_t k = 5; k < 10; ++k) send(k, "vz");
  EXPECT_EQ(states.back(), "running");
  EXPECT_TRUE(get().accepted);
  EXPECT_FALSE(Samples().empty());
}

}  // namespace
}  // namespace odonata::identifier
