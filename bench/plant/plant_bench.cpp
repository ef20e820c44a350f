// Simulated seconds per wall-clock second of the DI-MAV plant, and how the cost grows with blade
// strips and RK4 steps per wing beat. Counter "realtime_x" is the real-time factor (target ≥ 200
// at the default fidelity on one core).
#include <benchmark/benchmark.h>

#include "plant/dimav_plant.hpp"
#include "plant/trim_finder.hpp"

namespace {

using odonata::plant::CommandMatrix;
using odonata::plant::DimavPlant;
using odonata::plant::PlantConfig;

// Runs one simulated second per iteration in free flight from hover with a gentle manoeuvre.
void RunSeconds(benchmark::State& state, const PlantConfig& config) {
  const odonata::plant::TrimResult trim = odonata::plant::FindHoverTrim(config);
  DimavPlant plant(config);
  odonata::plant::InitialCondition ic;
  ic.state.position_m.z() = 100.0;
  ic.prior_command = trim.command;
  CommandMatrix command = trim.command;
  command(0, odonata::plant::kStrokeAmplitude) += 0.01;
  const int samples_per_s = static_cast<int>(config.integration.sample_rate_hz);
  plant.Reset(ic);
  double simulated_s = 0.0;
  for (auto _ : state) {
    for (int k = 0; k < samples_per_s; ++k) {
      if (plant.Step(command) != odonata::plant::StepStatus::kOk) plant.Reset(ic);
    }
    benchmark::DoNotOptimize(plant.output());
    simulated_s += 1.0;
  }
  state.counters["realtime_x"] = benchmark::Counter(simulated_s, benchmark::Counter::kIsRate);
  state.counters["strips"] = config.wing.strip_count;
  state.counters["steps_per_beat_at_trim"] =
      config.integration.sample_rate_hz * plant.steps_per_sample() / trim.freq_hz;
}

void BM_DefaultFidelity(benchmark::State& state) {
  RunSeconds(state, odonata::plant::DefaultPlantConfig());
}
BENCHMARK(BM_DefaultFidelity)->Unit(benchmark::kMillisecond);

void BM_BladeStrips(benchmark::State& state) {
  PlantConfig c = odonata::plant::DefaultPlantConfig();
  c.wing.strip_count = static_cast<int>(state.range(0));
  RunSeconds(state, c);
}
BENCHMARK(BM_BladeStrips)
    ->Arg(5)
    ->Arg(10)
    ->Arg(20)
    ->Arg(40)
    ->Arg(80)
    ->Unit(benchmark::kMillisecond);

// min_steps_per_beat at the 8 Hz frequency limit: 50 ⇒ 4 steps per 10 ms sample (default).
void BM_StepsPerBeat(benchmark::State& state) {
  PlantConfig c = odonata::plant::DefaultPlantConfig();
  c.integration.min_steps_per_beat = static_cast<int>(state.range(0));
  RunSeconds(state, c);
}
BENCHMARK(BM_StepsPerBeat)->Arg(50)->Arg(100)->Arg(200)->Arg(400)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
