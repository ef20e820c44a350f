// The online identifier at a paced rate with its default scheduled refits (issue 21 point 3):
// how long each sample takes from arrival to prediction (p50, p99, max) while refits run in the
// worker thread, and the process's CPU share. The model is the case: 7 regressor inputs
// (ny 3; two inputs, nu 2), rule cap 30. In-process: the LCM hop adds its own ~70 µs
// (run_pipeline_bench.sh). Run: build/bench/identifier/bench_refit_realtime [--seconds 130]
// [--horizon K]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "sysid/model/signal_ranges.hpp"
#include "sysid/online/online_identifier.hpp"
#include "sysid/selection/model_selection.hpp"

namespace {

using namespace odonata::sysid;

double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// A nonlinear two-input plant driven by held random levels (an APRBS).
Series Plant(int samples, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> level(-1.5, 1.5);
  std::uniform_int_distribution<int> hold(5, 40);
  Series s;
  s.inputs.resize(samples, 2);
  s.outputs = Eigen::MatrixXd::Zero(samples, 1);
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < samples;) {
      const double v = level(rng);
      for (int h = hold(rng); h > 0 && k < samples; --h) s.inputs(k++, i) = v;
    }
  for (int k = 2; k + 1 < samples; ++k) {
    const double y = s.outputs(k, 0), y1 = s.outputs(k - 1, 0), y2 = s.outputs(k - 2, 0);
    const double u1 = s.inputs(k, 0), u2 = s.inputs(k, 1), u1p = s.inputs(k - 1, 0);
    s.outputs(k + 1, 0) = 0.55 * y - 0.15 * y1 + 0.05 * y2 + 0.4 * std::tanh(2 * u1) +
                          0.15 * u2 * u1p + 0.1 * y / (1 + y * y) * u2;
  }
  return s;
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * double(v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"the online identifier at a paced rate with its scheduled refits"};
  double seconds = 130, rate = 100;
  bool no_refit = false;
  int horizon = 0;
  app.add_option("--seconds", seconds, "run length")->capture_default_str();
  app.add_option("--rate", rate, "samples per second")->capture_default_str();
  app.add_flag("--no-refit", no_refit, "the per-sample learner alone");
  app.add_option("--horizon", horizon,
                 "K > 1: refits choose K steps ahead (the identifier's refit_horizon), and a "
                 "landing judges its model K steps ahead; 0: free run")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const int n = static_cast<int>(seconds * rate);
  const Series data = Plant(n + 10, 3);
  RegressorSpec spec;
  spec.outputs = {"y"};
  spec.inputs = {"u1", "u2"};
  spec.output_lags = 3;
  spec.input_lags = 2;
  odonata::fuzzy::FuzzyModelConfig cfg;
  cfg.entropy.max_rules = 30;
  cfg.entropy.threshold = ThresholdForRadius(1.1);
  NarxModel model(spec, cfg);
  model.SetScaling(ScalingFromRanges(spec, RangesFromSeries(spec, data)));
  RefitSchedule refit = no_refit ? RefitSchedule{} : RefitSchedule::IdentifierDefault();
  refit.horizon = horizon;
  OnlineIdentifier id(model, refit);
  std::vector<double> micros;
  micros.reserve(static_cast<std::size_t>(n));
  double worst = 0;
  int64_t worst_at = 0, landed = 0;
  std::vector<int64_t> landings;
  const auto period = std::chrono::duration<double>(1.0 / rate);
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = CpuSeconds();
  int late = 0;
  for (int k = 0; k < n; ++k) {
    const auto due =
        t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(k * period);
    std::this_thread::sleep_until(due);
    const auto a = std::chrono::steady_clock::now();
    id.Push({k, data.outputs.row(k).transpose(), data.inputs.row(k).transpose()});
    const double us =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - a).count();
    micros.push_back(us);
    if (us > worst) {
      worst = us;
      worst_at = k;
    }
    if (us > 1e6 / rate) ++late;
    if (id.refits() != landed) {
      landed = id.refits();
      landings.push_back(k);
      std::fprintf(stderr,
                   "  refit %lld landed at sample %d (%.0f s): %d rules, took %.0f µs "
                   "(%lld selections, %lld kept the last refit's model, %lld linear models "
                   "landed)\n",
                   static_cast<long long>(landed), k, k / rate, id.model().total_rules(), us,
                   static_cast<long long>(id.selections()),
                   static_cast<long long>(id.incumbents_kept()),
                   static_cast<long long>(id.linear_landed()));
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = CpuSeconds() - cpu0;
  std::printf(
      "%s: %d samples at %.0f Hz (%.0f s), %lld refits landed (%lld failed), %d rules\n"
      "  arrival -> prediction: p50 %.1f µs, p99 %.1f µs, max %.0f µs (sample %lld); %d samples "
      "took longer than a period\n"
      "  CPU %.1f s in %.1f s: %.1f %% of one core (worker thread included)\n",
      no_refit ? "per-sample learner alone" : "default refits", n, rate, seconds,
      static_cast<long long>(id.refits()), static_cast<long long>(id.failed_refits()),
      id.model().total_rules(), Percentile(micros, 0.5), Percentile(micros, 0.99), worst,
      static_cast<long long>(worst_at), late, cpu, wall, 100 * cpu / wall);
  return 0;
}
