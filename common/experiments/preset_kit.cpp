#include "experiments/preset_kit.hpp"

#include "plant/angle_constants.hpp"
#include "signals/taper.hpp"

namespace odonata::experiments {
namespace {

std::uint32_t PhaseStreamId(Phase phase) {
  switch (phase) {
    case Phase::kTrain:
      return 1;
    case Phase::kValidate:
      return 2;
    case Phase::kSelect:
      return 3;
  }
  return 0;
}

double Clamp(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

}  // namespace

std::mt19937_64 Stream(std::uint64_t seed, Phase phase, std::uint64_t purpose) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    PhaseStreamId(phase), static_cast<std::uint32_t>(purpose)};
  return std::mt19937_64(seq);
}

double RandomPhaseRad(std::uint64_t seed, Phase phase, std::uint64_t purpose) {
  std::mt19937_64 rng = Stream(seed, phase, purpose);
  return 2.0 * plant::kPi * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

std::uint64_t NoiseSeed(std::uint64_t seed, Phase phase) {
  std::mt19937_64 rng = Stream(seed, phase, 99);
  return rng();
}

std::uint64_t AprbsSeed(std::uint64_t seed, Phase phase, std::uint64_t purpose) {
  std::mt19937_64 rng = Stream(seed, phase, 1000 + purpose);
  return rng();
}

double MeanFrequencyHz(const plant::CommandMatrix& c) {
  return c.col(plant::kFlapFrequency).mean();
}

void RunBuilder::Fill(std::size_t samples, double dt_s,
                      const std::function<void(double, plant::CommandMatrix*)>& fill,
                      const std::function<double(const plant::CommandMatrix&)>& applied,
                      const std::string& excitation_name) {
  run.commands.reserve(samples);
  std::vector<double> u;
  u.reserve(samples);
  for (std::size_t k = 0; k < samples; ++k) {
    plant::CommandMatrix c = trim.command;
    fill(static_cast<double>(k) * dt_s, &c);
    bool clamped = false;
    for (int w = 0; w < plant::kWingCount; ++w) {
      for (int i = 0; i < plant::kCommandsPerWing; ++i) {
        const double inside = Clamp(c(w, i), config.limits.min(i), config.limits.max(i));
        clamped = clamped || inside != c(w, i);
        c(w, i) = inside;
      }
    }
    if (clamped) ++run.clamped_samples;
    run.commands.push_back(c);
    if (applied) u.push_back(applied(c));
  }
  if (applied) {
    run.excitation_names.push_back(excitation_name);
    run.excitation_values.push_back(std::move(u));
  }
}

void RunBuilder::AddExcitation(const std::string& name,
                               const std::function<double(const plant::CommandMatrix&)>& channel) {
  std::vector<double> u;
  u.reserve(run.commands.size());
  for (const plant::CommandMatrix& c : run.commands) u.push_back(channel(c));
  run.excitation_names.push_back(name);
  run.excitation_values.push_back(std::move(u));
}

double ExcitationContext::Fade(double t) const {
  return signals::TukeyEnvelope(t, t_end_s, kRampS);
}

namespace {

// What every preset of the paper's section IV shares: its signals, the paper's H̄, membership
// function count and accuracy for comparison, 30 s phases and the start altitude.
ExperimentPreset PaperPreset(const std::string& name, const std::string& output,
                             std::vector<std::string> inputs, double h, const std::string& h_text,
                             int mfs, const std::string& accuracy) {
  ExperimentPreset p;
  p.name = name;
  p.output_column = output;
  p.input_columns = std::move(inputs);
  p.delay = 1;
  p.entropy_threshold = h;
  p.paper_entropy_text = h_text;
  p.paper_mf_count = mfs;
  p.paper_accuracy_text = accuracy;
  p.train_duration_s = 30.0;
  p.validate_duration_s = 30.0;
  p.select_duration_s = 30.0;
  p.start_altitude_m = kStartAltitudeM;
  return p;
}

}  // namespace

ExperimentPreset Actuator(const std::string& name, const std::string& output,
                          std::vector<std::string> inputs, double h, const std::string& h_text,
                          int mfs, const std::string& accuracy) {
  ExperimentPreset p = PaperPreset(name, output, std::move(inputs), h, h_text, mfs, accuracy);
  p.ny = 2;
  p.nu = 2;
  p.clamped_body = true;  // a test stand
  return p;
}

ExperimentPreset Attitude(const std::string& name, const std::string& output,
                          const std::string& input, double h, const std::string& h_text, int mfs,
                          const std::string& accuracy) {
  ExperimentPreset p = PaperPreset(name, output, {input}, h, h_text, mfs, accuracy);
  p.ny = 3;
  p.nu = 2;
  p.clamped_body = false;  // free flight, the onboard hold on
  p.attitude_hold = true;
  return p;
}

ExperimentPreset BeyondPaper(ExperimentPreset p, int ny, int nu, int decimate) {
  p.ny = ny;
  p.nu = nu;
  p.decimate = decimate;
  p.train_duration_s = p.select_duration_s = p.validate_duration_s = 60.0;
  p.beyond_paper = true;
  return p;
}

}  // namespace odonata::experiments
