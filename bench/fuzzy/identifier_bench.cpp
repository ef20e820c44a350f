// Identifier speed: one online step, inference alone beside fuzzylite on an identical rule
// base, and offline fit throughput. Run: build/bench/fuzzy/bench_identifier
//
// Targets (issue 2): a step at R = 41, N = 6 in ≤ 0.5 µs in the default (Release) build.

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

#include <benchmark/benchmark.h>

#include "fuzzy/fuzzy_model.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/online/settling_watch.hpp"

#ifdef ODONATA_HAVE_FUZZYLITE
#include <fl/Headers.h>
#endif

namespace {

using odonata::fuzzy::ConsequentKind;
using odonata::fuzzy::FuzzyModel;
using odonata::fuzzy::FuzzyModelConfig;

/// A model with exactly `rules` seeded random rules whose cap is reached, so a Learn() step
/// does the full entropy check but never grows (the steady state of an online identifier).
FuzzyModel MakeModel(int rules, int inputs, ConsequentKind kind) {
  FuzzyModelConfig cfg;
  cfg.inputs = inputs;
  cfg.consequent = kind;
  cfg.entropy.max_rules = rules;
  FuzzyModel m(cfg);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), w(0.2, 0.6);
  for (int j = 0; j < rules; ++j) {
    Eigen::VectorXd c(inputs), s(inputs);
    for (int i = 0; i < inputs; ++i) {
      c(i) = u(rng);
      s(i) = w(rng);
    }
    m.mutable_consequent().AddRule(c, u(rng), Eigen::ArrayXd::Constant(j, 1.0 / std::max(j, 1)));
    m.mutable_rule_base().AddRule(c, s);
  }
  return m;
}

std::vector<Eigen::VectorXd> Samples(int inputs, int count) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::VectorXd> xs(static_cast<std::size_t>(count), Eigen::VectorXd(inputs));
  for (auto& x : xs)
    for (int i = 0; i < inputs; ++i) x(i) = u(rng);
  return xs;
}

void StepArgs(benchmark::internal::Benchmark* b) {
  for (int n : {2, 6})
    for (int r : {3, 6, 18, 41, 100}) b->Args({r, n});
}

template <ConsequentKind kKind>
void BM_IdentifierStep(benchmark::State& state) {
  const int rules = static_cast<int>(state.range(0)), inputs = static_cast<int>(state.range(1));
  FuzzyModel m = MakeModel(rules, inputs, kKind);
  const auto xs = Samples(inputs, 1024);
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& x = xs[k++ & 1023];
    const auto r = m.Learn(x, 0.3 * x(0) - 0.2, odonata::fuzzy::LearnMode::kGrowAndTune);
    benchmark::DoNotOptimize(r);
  }
  if (m.rules() != rules) throw std::logic_error("the benchmark model grew");
  state.SetItemsProcessed(state.iterations());
  state.counters["rules"] = rules;
  state.counters["inputs"] = inputs;
}
BENCHMARK_TEMPLATE(BM_IdentifierStep, ConsequentKind::kSingleton)->Apply(StepArgs);
BENCHMARK_TEMPLATE(BM_IdentifierStep, ConsequentKind::kLinear)->Apply(StepArgs);

// What "seen enough" adds to each learned sample, beside the step above: Observe, and the state
// every prediction carries (States); one output whose N = 6 regressor is 3 output and 3 input
// lags.
void BM_SettlingWatchObserve(benchmark::State& state) {
  const int rules = static_cast<int>(state.range(0));
  odonata::sysid::RegressorSpec spec;
  spec.output_lags = 3;
  spec.input_lags = 3;
  spec.outputs = {"y"};
  spec.inputs = {"u"};
  FuzzyModelConfig cfg;
  cfg.consequent = ConsequentKind::kLinear;
  odonata::sysid::NarxModel model(spec, cfg);
  odonata::sysid::Scaling scaling;
  scaling.regressor_mid = Eigen::VectorXd::Zero(6);
  scaling.regressor_half = Eigen::VectorXd::Ones(6);
  scaling.output_mean = Eigen::VectorXd::Zero(1);
  scaling.output_std = Eigen::VectorXd::Ones(1);
  model.SetScaling(scaling);
  model.mutable_model(0) = MakeModel(rules, 6, ConsequentKind::kLinear);
  const auto xs = Samples(6, 1024);
  odonata::sysid::SettlingWatch watch;
  Eigen::VectorXd y(1), yhat(1);
  std::size_t k = 0;
  for (auto _ : state) {
    const auto& x = xs[k++ & 1023];
    y(0) = 0.3 * x(0) - 0.2;
    yhat(0) = 0.29 * x(0) - 0.2;
    watch.Observe(model, x, y, yhat);
    benchmark::DoNotOptimize(watch.States(model));
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["rules"] = rules;
}
BENCHMARK(BM_SettlingWatchObserve)->Arg(6)->Arg(41)->Arg(100);

void BM_InferenceOdonata(benchmark::State& state) {
  const int rules = static_cast<int>(state.range(0)), inputs = static_cast<int>(state.range(1));
  const FuzzyModel m = MakeModel(rules, inputs, ConsequentKind::kSingleton);
  const auto xs = Samples(inputs, 1024);
  std::size_t k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(m.Predict(xs[k++ & 1023]));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_InferenceOdonata)->Args({41, 6})->Args({100, 6})->Args({6, 2});

#ifdef ODONATA_HAVE_FUZZYLITE
/// The same rule base as a fuzzylite TSK engine: Gaussian terms with σ' = sqrt(σ² + ε) (so the
/// memberships are identical), algebraic-product conjunction, constant consequents, weighted
/// average defuzzification = our centre-average with s_j = 1.
struct FuzzyliteTwin {
  std::unique_ptr<fl::Engine> engine = std::make_unique<fl::Engine>();
  std::vector<fl::InputVariable*> inputs;  // owned by the engine
  fl::OutputVariable* output = nullptr;    // owned by the engine

  explicit FuzzyliteTwin(const FuzzyModel& m) {
    // fuzzylite treats activations below its machine epsilon (1e-6) as zero; odonata keeps
    // every rule's contribution, so lower it for an exact comparison.
    fl::fuzzylite::setMachEps(1e-300);
    const auto& rb = m.rule_base();
    for (int i = 0; i < m.inputs(); ++i) {
      // fuzzylite's API takes ownership of raw pointers; release() hands them over.
      auto in = std::make_unique<fl::InputVariable>("x" + std::to_string(i), -10, 10);
      for (int j = 0; j < rb.rules(); ++j) {
        const double s = rb.sigma(j, i);
        in->addTerm(std::make_unique<fl::Gaussian>("r" + std::to_string(j), rb.centre(j, i),
                                                   std::sqrt(s * s + odonata::fuzzy::kEpsilon))
                        .release());
      }
      inputs.push_back(in.get());
      engine->addInputVariable(in.release());
    }
    auto out = std::make_unique<fl::OutputVariable>("y", -1e6, 1e6);
    out->setDefuzzifier(std::make_unique<fl::WeightedAverage>("TakagiSugeno").release());
    out->setAggregation(nullptr);
    const Eigen::VectorXd b = m.consequent().Parameters();
    for (int j = 0; j < rb.rules(); ++j) {
      out->addTerm(std::make_unique<fl::Constant>("b" + std::to_string(j), b(j)).release());
    }
    output = out.get();
    engine->addOutputVariable(out.release());
    auto block = std::make_unique<fl::RuleBlock>();
    block->setConjunction(std::make_unique<fl::AlgebraicProduct>().release());
    block->setActivation(std::make_unique<fl::General>().release());
    for (int j = 0; j < rb.rules(); ++j) {
      std::string text = "if ";
      for (int i = 0; i < m.inputs(); ++i) {
        text += (i ? " and x" : "x") + std::to_string(i) + " is r" + std::to_string(j);
      }
      text += " then y is b" + std::to_string(j);
      block->addRule(fl::Rule::parse(text, engine.get()));
    }
    engine->addRuleBlock(block.release());
    std::string status;
    if (!engine->isReady(&status))
      throw std::runtime_error("fuzzylite engine not ready: " + status);
  }

  double Evaluate(const Eigen::VectorXd& x) {
    for (std::size_t i = 0; i < inputs.size(); ++i)
      inputs[i]->setValue(x(static_cast<Eigen::Index>(i)));
    engine->process();
    return output->getValue();
  }
};

void BM_InferenceFuzzylite(benchmark::State& state) {
  const int rules = static_cast<int>(state.range(0)), inputs = static_cast<int>(state.range(1));
  const FuzzyModel m = MakeModel(rules, inputs, ConsequentKind::kSingleton);
  FuzzyliteTwin twin(m);
  const auto xs = Samples(inputs, 1024);
  // Same output check before timing: the ratio only means something for identical results.
  double worst = 0;
  for (const auto& x : xs) worst = std::max(worst, std::abs(twin.Evaluate(x) - m.Predict(x)));
  state.counters["max_abs_diff_vs_odonata"] = worst;
  if (worst > 1e-9) {
    std::fprintf(stderr, "fuzzylite %.17g odonata %.17g\n", twin.Evaluate(xs[0]), m.Predict(xs[0]));
    state.SkipWithError("fuzzylite and odonata disagree");
  }
  std::size_t k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(twin.Evaluate(xs[k++ & 1023]));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_InferenceFuzzylite)->Args({41, 6})->Args({100, 6})->Args({6, 2});
#endif

void BM_OfflineFitThroughput(benchmark::State& state) {
  // 100k samples of the Narendra plant, default configuration (one pass + least squares).
  const int n = 100000;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> dist(-2, 2);
  odonata::sysid::Series s;
  s.inputs.resize(n, 1);
  s.outputs = Eigen::MatrixXd::Zero(n, 1);
  for (int k = 0; k < n; ++k) s.inputs(k, 0) = dist(rng);
  for (int k = 0; k + 1 < n; ++k) {
    const double y = s.outputs(k, 0);
    s.outputs(k + 1, 0) = y / (1 + y * y) + std::pow(s.inputs(k, 0), 3);
  }
  odonata::sysid::RegressorSpec spec{1, 1, 1, {"y"}, {"u"}};
  FuzzyModelConfig cfg;
  cfg.consequent = static_cast<ConsequentKind>(state.range(0));
  int rules = 0;
  for (auto _ : state) {
    odonata::sysid::NarxModel m(spec, cfg);
    Train(m, s, odonata::sysid::TrainOptions{});
    rules = m.total_rules();
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["rules"] = rules;
}
BENCHMARK(BM_OfflineFitThroughput)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
