// Simulation-error training: the multiple-shooting gradient against finite differences, and
// what it is for — on a system with output noise, one-step training is biased and simulation
// training is not.
#include "sysid/estimation/simulation_error_training.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/arx_model.hpp"

namespace odonata::sysid {
namespace {

RegressorSpec Spec(int ny, int nu) {
  RegressorSpec spec;
  spec.outputs = {"y"};
  spec.inputs = {"u"};
  spec.output_lags = ny;
  spec.input_lags = nu;
  return spec;
}

// A second-order nonlinear plant, smooth enough for a few rules.
Series Plant(int samples, unsigned seed, double noise) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> level(-1.0, 1.0);
  std::normal_distribution<double> n(0.0, noise);
  Series s;
  s.inputs.resize(samples, 1);
  s.outputs.resize(samples, 1);
  double u = 0, x1 = 0, x2 = 0;
  for (int k = 0; k < samples; ++k) {
    if (k % 10 == 0) u = level(rng);  // held steps: slow enough to show the dynamics
    s.inputs(k, 0) = u;
    s.outputs(k, 0) = x1 + (noise > 0 ? n(rng) : 0.0);
    const double next = 0.85 * x1 - 0.1 * x2 + 0.3 * std::tanh(1.5 * u);
    x2 = x1;
    x1 = next;
  }
  return s;
}

NarxModel Trained(const RegressorSpec& spec, const Series& s, double threshold) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  cfg.entropy.threshold = threshold;
  cfg.entropy.max_rules = 8;
  NarxModel m(spec, cfg);
  TrainOptions t;
  t.epochs = 3;
  Train(m, s, t);
  return m;
}

// The one-rule model with a linear consequent (ARX on the regressor), by one-step least squares.
NarxModel LeastSquaresLinear(const RegressorSpec& spec, const Series& s) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  cfg.entropy.max_rules = 1;
  cfg.entropy.threshold = 0.0;
  NarxModel m(spec, cfg);
  Train(m, s, TrainOptions{});
  return m;
}

TEST(SimulationErrorTraining, GradientMatchesFiniteDifferences) {
  for (const auto kind : {fuzzy::ConsequentKind::kLinear, fuzzy::ConsequentKind::kSingleton}) {
    const RegressorSpec spec = Spec(2, 2);
    const Series s = Plant(300, 3, 0.02);
    fuzzy::FuzzyModelConfig cfg;
    cfg.consequent = kind;
    cfg.entropy.threshold = 0.45;
    cfg.entropy.max_rules = 6;
    NarxModel m(spec, cfg);
    TrainOptions t;
    t.epochs = 2;
    Train(m, s, t);
    ASSERT_GE(m.total_rules(), 2);
    SimulationGradient g;
    const int horizon = 7;  // several windows, one of them short
    const double loss = SimulationLoss(m, s, horizon, &g);
    ASSERT_TRUE(std::isfinite(loss));
    const double h = 1e-6;
    auto& fm = m.mutable_model(0);
    const int r = fm.rules(), n = spec.size();
    double worst = 0.0;
    auto check = [&](double analytic, double numeric) {
      worst = std::max(worst, std::abs(analytic - numeric) / std::max(1e-3, std::abs(numeric)));
    };
    for (int j = 0; j < r; ++j) {
      for (int i = 0; i < n; ++i) {
        Eigen::ArrayXXd d = Eigen::ArrayXXd::Zero(r, n), z = Eigen::ArrayXXd::Zero(r, n);
        d(j, i) = h;
        fm.StepPremises(d, z);
        const double up = SimulationLoss(m, s, horizon);
        fm.StepPremises(-2 * d, z);
        const double down = SimulationLoss(m, s, horizon);
        fm.StepPremises(d, z);
        check(g.centres[0](j, i), (up - down) / (2 * h));
        fm.StepPremises(z, d);
        const double su = SimulationLoss(m, s, horizon);
        fm.StepPremises(z, -2 * d);
        const double sd = SimulationLoss(m, s, horizon);
        fm.StepPremises(z, d);
        check(g.sigmas[0](j, i), (su - sd) / (2 * h));
      }
    }
    const Eigen::VectorXd p = fm.consequent().Parameters();
    for (Eigen::Index k = 0; k < p.size(); ++k) {
      Eigen::VectorXd q = p;
      q(k) += h;
      fm.mutable_consequent().SetParameters(q);
      const double up = SimulationLoss(m, s, horizon);
      q(k) -= 2 * h;
      fm.mutable_consequent().SetParameters(q);
      const double down = SimulationLoss(m, s, horizon);
      fm.mutable_consequent().SetParameters(p);
      check(g.consequents[0](k), (up - down) / (2 * h));
    }
    EXPECT_LT(worst, 1e-4) << fuzzy::ToString(kind);
  }
}

TEST(SimulationErrorTraining, LowersTheSimulationLossAndKeepsTheStructure) {
  const RegressorSpec spec = Spec(2, 2);
  const Series s = Plant(600, 5, 0.05);
  NarxModel m = Trained(spec, s, 0.4);
  const int rules = m.total_rules();
  SimulationTrainOptions o;
  o.stages = {{30, 40}};
  const double before = SimulationLoss(m, s, 30);
  const auto report = TrainOnSimulationError(m, s, o);
  EXPECT_DOUBLE_EQ(report.initial_loss, before);
  EXPECT_LT(SimulationLoss(m, s, 30), 0.9 * before);
  EXPECT_EQ(m.total_rules(), rules);
  ASSERT_EQ(report.kept.size(), 1u);
  EXPECT_EQ(report.kept[0].steps, 40);
}

// Without a hold-out a schedule is replayed exactly: the same steps give the same model, which is
// how the final fit repeats what the selection kept.
TEST(SimulationErrorTraining, AScheduleReplaysBitForBit) {
  const RegressorSpec spec = Spec(2, 2);
  const Series s = Plant(600, 5, 0.05);
  const Series holdout = Plant(300, 9, 0.05);
  NarxModel a = Trained(spec, s, 0.4);
  NarxModel b = a;
  SimulationTrainOptions o;
  o.stages = {{10, 15}, {40, 15}, {160, 15}};
  o.holdout = &holdout;
  o.patience = 5;
  const auto report = TrainOnSimulationError(a, s, o);
  SimulationTrainOptions replay;
  replay.stages = report.kept;
  TrainOnSimulationError(b, s, replay);
  EXPECT_EQ(a.ToJson(), b.ToJson());
}

// Output noise enters a one-step model's regressor (errors in variables): least squares on
// noisy lags is biased. The simulation error does not feed the noisy outputs back, so the linear
// model trained on it (output error) sits closer to the true plant in free run.
TEST(SimulationErrorTraining, OutputNoiseBiasesOneStepTrainingButNotSimulationTraining) {
  RegressorSpec spec = Spec(2, 2);
  const Series noisy = Plant(3000, 11, 0.2);
  const Series clean = Plant(3000, 11, 0.0);  // the same inputs, no noise: the truth
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  cfg.entropy.threshold = 0.45;
  cfg.entropy.max_rules = 4;
  NarxModel one_step(spec, cfg);
  TrainOptions t;
  t.epochs = 3;
  Train(one_step, noisy, t);
  NarxModel simulation = one_step;
  SimulationTrainOptions o;
  o.stages = {{10, 30}, {40, 30}, {160, 30}};
  TrainOnSimulationError(simulation, noisy, o);
  const double before = one_step.Ndei(clean, true);
  const double after = simulation.Ndei(clean, true);
  EXPECT_LT(after, 0.6 * before) << "free-run NDEI against the noise-free output: one-step "
                                 << before << ", simulation-trained " << after;
  EXPECT_LT(after, 0.05);  // the one-step model is above it
}

// The plant above under a slow coloured disturbance (AR(1), pole 0.995) instead of white noise: the
// one-step predictor leans on the measured lags to follow it, a K-step one cannot.
Series DisturbedPlant(int samples, unsigned seed) {
  Series s = Plant(samples, seed, 0.0);
  std::mt19937_64 rng(seed + 1000);
  std::normal_distribution<double> w(0.0, 0.05);
  double v = 0;
  for (int k = 0; k < samples; ++k) {
    s.outputs(k, 0) += v;
    v = 0.995 * v + w(rng);
  }
  return s;
}

// Scored K steps ahead on a disturbed record, simulation training trades one-step accuracy for
// K-step accuracy; with a one-step bound no step beyond it is kept (on this plant the K-step
// score only improves once the one-step NDEI has risen past half way, so the bounded run keeps
// its start), and a bound at the unbounded run's own value takes nothing away
// (docs/identifier.md §12).
TEST(SimulationErrorTraining, AOneStepBoundLimitsTheStepsKept) {
  const RegressorSpec spec = Spec(2, 2);
  const Series train = DisturbedPlant(2000, 21);
  const Series holdout = DisturbedPlant(800, 22);
  const NarxModel start = Trained(spec, train, 0.4);
  SimulationTrainOptions o;
  o.stages = {{10, 30}, {40, 30}};
  o.holdout = &holdout;
  o.holdout_horizon = 40;
  o.patience = 0;
  const double one_step = start.NdeiAhead(holdout, 1);
  const double ahead = start.NdeiAhead(holdout, 40);
  NarxModel free = start;
  TrainOnSimulationError(free, train, o);
  const double free_one_step = free.NdeiAhead(holdout, 1);
  ASSERT_GT(free_one_step, 1.03 * one_step)
      << "unbounded, the kept step gives one-step accuracy away (else this test shows nothing)";
  ASSERT_LT(free.NdeiAhead(holdout, 40), 0.95 * ahead);
  // Half way between: no step beyond the bound is kept, and what is kept replays exactly, as the
  // final fit replays the schedule.
  NarxModel bounded = start;
  o.one_step_bound = 0.5 * (one_step + free_one_step);
  const auto report = TrainOnSimulationError(bounded, train, o);
  EXPECT_LE(bounded.NdeiAhead(holdout, 1), o.one_step_bound);
  EXPECT_LE(bounded.NdeiAhead(holdout, 40), ahead);
  NarxModel replayed = start;
  SimulationTrainOptions replay;
  replay.stages = report.kept;
  TrainOnSimulationError(replayed, train, replay);
  EXPECT_EQ(replayed.ToJson(), bounded.ToJson());
  // At the unbounded run's own one-step NDEI the bound takes nothing away: the same step is kept.
  NarxModel at_free = start;
  o.one_step_bound = free_one_step;
  TrainOnSimulationError(at_free, train, o);
  EXPECT_EQ(at_free.ToJson(), free.ToJson());
}

// The Levenberg–Marquardt stage's normal equations come from forward sensitivities; the
// iRprop− gradient from backpropagation through time: two derivations of one quantity, ∂L/∂θ =
// 2 Jᵀe, which must agree — with outputs held at a saturation limit too (zero sensitivity there).
TEST(SimulationErrorTraining, ForwardSensitivitiesAgreeWithBackpropagationThroughTime) {
  const RegressorSpec spec = Spec(2, 2);
  const Series s = Plant(300, 5, 0.05);
  for (const bool limited : {false, true}) {
    NarxModel m = Trained(spec, s, 0.45);
    ASSERT_GT(m.total_rules(), 1);
    if (limited) {
      OutputLimits l;
      l.lower = Eigen::VectorXd::Constant(1, -0.2);
      l.upper = Eigen::VectorXd::Constant(1, 0.25);
      m.SetLimits(l);
    }
    for (const int horizon : {7, 40}) {
      SimulationGradient g;
      const double loss = SimulationLoss(m, s, horizon, &g);
      Eigen::MatrixXd jtj;
      Eigen::VectorXd jte;
      const double same = NormalEquations(m, s, horizon, false, jtj, jte);
      EXPECT_NEAR(same, loss, 1e-9 * loss);
      ASSERT_EQ(jte.size(), g.consequents[0].size());
      EXPECT_LT((2.0 * jte - g.consequents[0]).norm(), 1e-8 * (1.0 + g.consequents[0].norm()))
          << "horizon " << horizon << (limited ? ", limited" : "");
      EXPECT_TRUE(jtj.isApprox(jtj.transpose()));
      // With the premises: consequents, then centres and widths (rules × inputs, by column).
      const double with_premises = NormalEquations(m, s, horizon, true, jtj, jte);
      EXPECT_NEAR(with_premises, loss, 1e-9 * loss);
      const Eigen::Index q = g.consequents[0].size(), rn = g.centres[0].size();
      ASSERT_EQ(jte.size(), q + 2 * rn);
      Eigen::VectorXd whole(q + 2 * rn);
      whole << g.consequents[0], Eigen::Map<const Eigen::VectorXd>(g.centres[0].data(), rn),
          Eigen::Map<const Eigen::VectorXd>(g.sigmas[0].data(), rn);
      EXPECT_LT((2.0 * jte - whole).norm(), 1e-8 * (1.0 + whole.norm()))
          << "premises, horizon " << horizon << (limited ? ", limited" : "");
    }
  }
}

// A linear plant with output noise: the Levenberg–Marquardt stage takes the one-rule model to its
// output-error optimum in a few iterations, far closer to the truth in free run than one-step
// least squares, and a schedule replays it bit for bit.
TEST(SimulationErrorTraining, LevenbergMarquardtTakesTheLinearModelToItsOutputErrorOptimum) {
  const RegressorSpec spec = Spec(2, 2);
  // The plant of Plant() without its tanh: a linear model can be the truth.
  auto linear_plant = [](double noise) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> level(-1.0, 1.0);
    std::normal_distribution<double> n(0.0, noise);
    Series s;
    s.inputs.resize(2000, 1);
    s.outputs.resize(2000, 1);
    double u = 0, x1 = 0, x2 = 0;
    for (int k = 0; k < 2000; ++k) {
      if (k % 10 == 0) u = level(rng);
      s.inputs(k, 0) = u;
      s.outputs(k, 0) = x1 + (noise > 0 ? n(rng) : 0.0);
      const double next = 0.85 * x1 - 0.1 * x2 + 0.3 * u;
      x2 = x1;
      x1 = next;
    }
    return s;
  };
  const Series noisy = linear_plant(0.2);
  const Series clean = linear_plant(0.0);
  NarxModel least_squares = LeastSquaresLinear(spec, noisy);
  NarxModel lm = least_squares;
  SimulationTrainOptions o;
  o.stages = {{640, 50, true}};
  const SimulationTrainReport r = TrainOnSimulationError(lm, noisy, o);
  ASSERT_EQ(r.kept.size(), 1u);
  EXPECT_TRUE(r.kept[0].gauss_newton);
  EXPECT_LT(r.kept[0].steps, 50) << "it converges";
  EXPECT_LT(SimulationLoss(lm, noisy, 640), r.initial_loss);
  const double before = least_squares.Ndei(clean, true);
  const double after = lm.Ndei(clean, true);
  EXPECT_LT(after, 0.7 * before) << "free-run NDEI against the noise-free output: least squares "
                                 << before << ", output error " << after;
  NarxModel again = least_squares;
  SimulationTrainOptions replay;
  replay.stages = r.kept;
  TrainOnSimulationError(again, noisy, replay);
  EXPECT_EQ(again.ToJson().dump(), lm.ToJson().dump());
}

// From the linear model: a rule base starts as the one-rule model's output-error fit (every rule
// the same consequent, the same free run), and the stage after it trains every parameter.
TEST(SimulationErrorTraining, FromTheLinearModelEveryRuleStartsAtItsOutputErrorFit) {
  const RegressorSpec spec = Spec(2, 2);
  const Series s = Plant(600, 7, 0.1);
  NarxModel fuzzy = Trained(spec, s, 0.45);
  ASSERT_GT(fuzzy.total_rules(), 1);
  // Trained on the same data: the same scaling, so the consequents mean the same in both.
  NarxModel linear = LeastSquaresLinear(spec, s);
  SimulationTrainOptions o;
  o.stages = {{160, 50, true}};
  TrainOnSimulationError(linear, s, o);
  // Tied normal equations are the full ones seen through the tie: Tᵀ JᵀJ T and Tᵀ Jᵀe.
  const Eigen::Index w = spec.size() + 1, rules = fuzzy.model(0).rules();
  Eigen::MatrixXd tie = Eigen::MatrixXd::Zero(rules * w, w);
  for (Eigen::Index j = 0; j < rules; ++j) tie.middleRows(j * w, w).setIdentity();
  Eigen::MatrixXd full_jtj, tied_jtj;
  Eigen::VectorXd full_jte, tied_jte;
  const double full_loss = NormalEquations(fuzzy, s, 40, false, full_jtj, full_jte);
  EXPECT_EQ(NormalEquations(fuzzy, s, 40, false, tied_jtj, tied_jte, &tie), full_loss);
  EXPECT_TRUE(tied_jtj.isApprox(tie.transpose() * full_jtj * tie, 1e-10));
  EXPECT_TRUE(tied_jte.isApprox(tie.transpose() * full_jte, 1e-10));
  NarxModel started = fuzzy;
  o.stages = {{160, 50, true, true}};
  const SimulationTrainReport r = TrainOnSimulationError(started, s, o);
  ASSERT_EQ(r.kept.size(), 1u);
  EXPECT_TRUE(r.kept[0].from_linear);
  EXPECT_EQ(started.total_rules(), fuzzy.total_rules()) << "the rule structure stays";
  const Eigen::VectorXd theta = started.model(0).consequent().Parameters();
  const Eigen::VectorXd shared = linear.model(0).consequent().Parameters();
  for (Eigen::Index j = 0; j < theta.size() / shared.size(); ++j)
    EXPECT_LT((theta.segment(j * shared.size(), shared.size()) - shared).norm(),
              1e-6 * shared.norm())
        << "rule " << j;
  EXPECT_NEAR(SimulationLoss(started, s, 160), SimulationLoss(linear, s, 160),
              1e-8 * SimulationLoss(linear, s, 160));
  // Then Levenberg–Marquardt on every parameter lowers the loss further, premises included.
  NarxModel whole = started;
  o.stages = {{160, 50, true}};
  TrainOnSimulationError(whole, s, o);
  EXPECT_LT(SimulationLoss(whole, s, 160), 0.99 * SimulationLoss(started, s, 160));
  double moved = 0.0;
  for (int j = 0; j < whole.model(0).rules(); ++j)
    for (int i = 0; i < spec.size(); ++i)
      moved = std::max(moved, std::abs(whole.model(0).rule_base().centre(j, i) -
                                       started.model(0).rule_base().centre(j, i)));
  EXPECT_GT(moved, 1e-6) << "the centres move too";
  // A singleton rule base cannot hold a linear model: the stage leaves it as it is.
  fuzzy::FuzzyModelConfig single;
  single.consequent = fuzzy::ConsequentKind::kSingleton;
  single.entropy.max_rules = 8;
  single.entropy.threshold = 0.45;
  NarxModel singleton(spec, single);
  Train(singleton, s, TrainOptions{});
  NarxModel untouched = singleton;
  o.stages = {{160, 50, true, true}};
  TrainOnSimulationError(untouched, s, o);
  EXPECT_EQ(untouched.ToJson().dump(), singleton.ToJson().dump());
}

TEST(SimulationErrorTraining, NeedsOutputLags) {
  const RegressorSpec spec = Spec(0, 2);
  fuzzy::FuzzyModelConfig cfg;
  NarxModel m(spec, cfg);
  SimulationTrainOptions o;
  EXPECT_THROW(TrainOnSimulationError(m, Plant(50, 1, 0.0), o), std::invalid_argument);
}

}  // namespace
}  // namespace odonata::sysid
