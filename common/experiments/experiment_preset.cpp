#include "experiments/experiment_preset.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>

#include "plant/angle_constants.hpp"
#include "signals/aprbs.hpp"
#include "signals/chirp.hpp"
#include "signals/gaussian_noise.hpp"
#include "signals/multisine.hpp"
#include "signals/taper.hpp"

namespace odonata::experiments {
namespace {

using plant::CommandMatrix;
using plant::kFlapFrequency;
using plant::kPi;
using plant::kRadPerDeg;
using plant::kStrokeAmplitude;
using plant::kStrokePlaneAngle;
using plant::kWingCount;

// Every free-flight experiment starts at hover trim this high: far enough that no preset reaches
// the ground within its run, so the ground never shapes identification data.
constexpr double kStartAltitudeM = 50.0;
// Fade-in/out of zero-mean attitude excitations (s).
constexpr double kRampS = 1.0;
// The paper's noise power (section IV-B1), 1-ohm convention: variance 0.01, σ = 0.1 rad.
constexpr double kNoisePowerW = 0.01;
// Cut at ±2.5σ (power kept, see GaussianNoise) so chirp + noise never meets the φ₀ limit.
constexpr double kNoiseClipSigmas = 2.5;

// Wing groups (0-based rows): 1 fore-left, 2 hind-left, 3 hind-right, 4 fore-right.
constexpr int kLeft[2] = {0, 1};
constexpr int kRight[2] = {2, 3};
constexpr int kFront[2] = {0, 3};
constexpr int kBack[2] = {1, 2};

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

// Independent random stream per (seed, phase, purpose).
std::mt19937_64 Stream(std::uint64_t seed, Phase phase, std::uint64_t purpose) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    PhaseStreamId(phase), static_cast<std::uint32_t>(purpose)};
  return std::mt19937_64(seq);
}

double RandomPhaseRad(std::uint64_t seed, Phase phase, std::uint64_t purpose) {
  std::mt19937_64 rng = Stream(seed, phase, purpose);
  return 2.0 * kPi * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

std::uint64_t NoiseSeed(std::uint64_t seed, Phase phase) {
  std::mt19937_64 rng = Stream(seed, phase, 99);
  return rng();
}

double Clamp(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

// Mean of a command entry over a pair of wings (exact when the two are equal).
double PairMean(const CommandMatrix& c, const int (&wings)[2], int input) {
  return 0.5 * (c(wings[0], input) + c(wings[1], input));
}

// One signal per phase, the selection and validation signals of the same family as training's.
template <class Train, class Select, class Validate>
double ByPhase(Phase phase, const Train& train, const Select& select, const Validate& validate,
               double t_s) {
  switch (phase) {
    case Phase::kTrain:
      return train.Value(t_s);
    case Phase::kSelect:
      return select.Value(t_s);
    case Phase::kValidate:
      break;
  }
  return validate.Value(t_s);
}

// Builds a run where `fill(k, t_s, command, u)` writes sample k's command (starting from the trim
// command) and its scalar excitation u. Commands are clamped; u is recomputed by `applied` (one of
// the *ChannelRad readers) from the clamped command, so the excitation column is exactly the
// designed command's channel. What the wings did also holds the attitude hold's correction: that
// is the *_applied_* column odonata-sim writes from the command it applies.
struct Builder {
  const plant::PlantConfig& config;
  const plant::TrimResult& trim;
  ExperimentRun run;

  void Fill(std::size_t samples, double dt_s,
            const std::function<void(double, CommandMatrix*)>& fill,
            const std::function<double(const CommandMatrix&)>& applied,
            const std::string& excitation_name) {
    run.commands.reserve(samples);
    std::vector<double> u;
    u.reserve(samples);
    for (std::size_t k = 0; k < samples; ++k) {
      CommandMatrix c = trim.command;
      fill(static_cast<double>(k) * dt_s, &c);
      bool clamped = false;
      for (int w = 0; w < kWingCount; ++w) {
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

  // One more scalar column, read from the (clamped) commands already filled.
  void AddExcitation(const std::string& name,
                     const std::function<double(const CommandMatrix&)>& channel) {
    std::vector<double> u;
    u.reserve(run.commands.size());
    for (const CommandMatrix& c : run.commands) u.push_back(channel(c));
    run.excitation_names.push_back(name);
    run.excitation_values.push_back(std::move(u));
  }
};

// Seed of an APRBS stream: independent per (seed, phase, purpose), like the chirp phases.
std::uint64_t AprbsSeed(std::uint64_t seed, Phase phase, std::uint64_t purpose) {
  std::mt19937_64 rng = Stream(seed, phase, 1000 + purpose);
  return rng();
}

// Mean flapping frequency of the four wings (Hz).
double MeanFrequencyHz(const CommandMatrix& c) { return c.col(kFlapFrequency).mean(); }

ExperimentPreset Actuator(const std::string& name, const std::string& output,
                          std::vector<std::string> inputs, double h, const std::string& h_text,
                          int mfs, const std::string& accuracy) {
  ExperimentPreset p;
  p.name = name;
  p.output_column = output;
  p.input_columns = std::move(inputs);
  p.ny = 2;
  p.nu = 2;
  p.delay = 1;
  p.entropy_threshold = h;
  p.paper_entropy_text = h_text;
  p.paper_mf_count = mfs;
  p.paper_accuracy_text = accuracy;
  p.train_duration_s = 30.0;
  p.validate_duration_s = 30.0;
  p.select_duration_s = 30.0;
  p.clamped_body = true;
  p.start_altitude_m = kStartAltitudeM;
  return p;
}

ExperimentPreset Attitude(const std::string& name, const std::string& output,
                          const std::string& input, double h, const std::string& h_text, int mfs,
                          const std::string& accuracy) {
  ExperimentPreset p;
  p.name = name;
  p.output_column = output;
  p.input_columns = {input};
  p.ny = 3;
  p.nu = 2;
  p.delay = 1;
  p.entropy_threshold = h;
  p.paper_entropy_text = h_text;
  p.paper_mf_count = mfs;
  p.paper_accuracy_text = accuracy;
  p.train_duration_s = 30.0;
  p.validate_duration_s = 30.0;
  p.select_duration_s = 30.0;
  p.clamped_body = false;
  p.start_altitude_m = kStartAltitudeM;
  p.attitude_hold = true;
  return p;
}

constexpr const char* kNotInPaper = "not in the paper";

// What the experiments beyond the paper share: 60 s phases, identified at a decimated rate.
ExperimentPreset BeyondPaper(ExperimentPreset p, int ny, int nu, int decimate) {
  p.ny = ny;
  p.nu = nu;
  p.decimate = decimate;
  p.train_duration_s = p.select_duration_s = p.validate_duration_s = 60.0;
  p.beyond_paper = true;
  return p;
}

std::vector<ExperimentPreset> MakePresets() {
  std::vector<ExperimentPreset> v;
  {
    ExperimentPreset p = Actuator("actuator_fz", "fz1_n", {"w1_freq_hz", "w1_amp_rad"}, 0.007,
                                  "0.178 -> 0.007", 18, "\"highly accurate\"");
    p.description = "wing-beat mean vertical force of one wing on a test stand, varying f and phi0";
    p.train_excitation =
        "all wings: f = 6.0 + 0.5 chirp(0.02->0.5 Hz) Hz (5.5-6.5 Hz); phi0 = 50 deg + 30 deg "
        "linear chirp(0.05->5 Hz)";
    p.validate_excitation =
        "all wings: f = 6.0 + 1.0 log-chirp(0.03->0.8 Hz) Hz (5-7 Hz); phi0 = 50 deg + 25 deg "
        "log-chirp(0.1->8 Hz)";
    p.select_excitation =
        "all wings: f = 6.0 + 0.75 chirp(0.025->0.65 Hz) Hz (5.25-6.75 Hz); phi0 = 50 deg + 28 "
        "deg linear chirp(0.07->6.5 Hz)";
    v.push_back(p);
  }
  {
    ExperimentPreset p =
        Actuator("actuator_fx", "fx1_n", {"w1_beta_rad", "w1_freq_hz", "w1_amp_rad"}, 0.002,
                 "0.002", 8, "> 80 %");
    p.description =
        "wing-beat mean horizontal force of one wing on a test stand, varying beta, f and phi0";
    p.train_excitation = "as actuator_fz training, plus beta = 10 deg chirp(0.02->1 Hz)";
    p.validate_excitation = "as actuator_fz validation, plus beta = 8 deg log-chirp(0.03->2 Hz)";
    p.select_excitation = "as actuator_fz selection, plus beta = 9 deg chirp(0.025->1.5 Hz)";
    v.push_back(p);
  }
  {
    ExperimentPreset p = Attitude("vertical_velocity", "vz_mps", "u_vertical_applied_rad", 0.05,
                                  "0.05", 41, "good (figure only)");
    p.ny = 2;
    p.train_duration_s = 40.0;
    p.validate_duration_s = 40.0;
    p.select_duration_s = 40.0;
    p.description = "body vertical velocity under the same phi0 on all four wings";
    p.train_excitation =
        "all wings: phi0 = phi0c + u, u = 0.19 rad linear chirp(0.05->5 Hz) + Gaussian noise "
        "0.01 W cut at 2.5 sigma; f = trim; attitude hold on";
    p.validate_excitation =
        "all wings: phi0 = phi0c + u, u = 0.17 rad log-chirp(0.05->6 Hz) + Gaussian noise 0.01 W "
        "cut at 2.5 sigma (other stream); f = trim; attitude hold on";
    p.select_excitation =
        "all wings: phi0 = phi0c + u, u = 0.18 rad linear chirp(0.06->5.5 Hz) + Gaussian noise "
        "0.01 W cut at 2.5 sigma (a third stream); f = trim; attitude hold on";
    v.push_back(p);
  }
  {
    ExperimentPreset p =
        Attitude("roll", "roll_rad", "u_roll_applied_rad", 0.01, "0.01", 6, "92.5 % validation");
    p.description =
        "roll under inverse phi0 chirps, left (1, 2) against right (3, 4); input: the applied "
        "differential, hold included (open loop)";
    p.train_excitation =
        "phi0 = trim +/- u (left +, right -), u = 3 deg linear chirp(0.1->3 Hz), 1 s fades; "
        "attitude hold on";
    p.validate_excitation =
        "phi0 = trim +/- u (left +, right -), u = 5 deg log-chirp(0.15->4 Hz), 1 s fades; "
        "attitude hold on";
    p.select_excitation =
        "phi0 = trim +/- u (left +, right -), u = 4 deg linear chirp(0.12->3.5 Hz), 1 s fades; "
        "attitude hold on";
    v.push_back(p);
  }
  {
    ExperimentPreset p = Attitude("pitch", "pitch_rad", "u_pitch_applied_rad", 0.001, "0.001", 3,
                                  "\"reasonably good\"");
    p.description =
        "pitch under front (1, 4) against back (2, 3) differences in amplitude; input: the "
        "applied differential, hold included (open loop)";
    p.train_excitation =
        "front: phi0 = trim + u; back: phi0 = trim - u; u = 1 deg linear chirp(0.1->3 Hz), 1 s "
        "fades; attitude hold on (no f differential: it drifts the fore/hind phase)";
    p.validate_excitation =
        "same mapping, u = 1.5 deg log-chirp(0.15->4 Hz), 1 s fades; attitude hold on";
    p.select_excitation =
        "same mapping, u = 1.25 deg linear chirp(0.12->3.5 Hz), 1 s fades; attitude hold on";
    v.push_back(p);
  }
  {
    ExperimentPreset p =
        Attitude("yaw", "yaw_rad", "u_yaw_applied_rad", 0.25, "0.25", 34, "about 98 %");
    p.description =
        "yaw under opposite stroke-plane angles, left (1, 2) -u against right (3, 4) +u; input: "
        "the applied differential (the hold does not act on beta)";
    p.train_excitation =
        "beta = -u left, +u right, u = 20 deg linear chirp(0.2->4 Hz), 1 s fades; attitude hold on";
    p.validate_excitation =
        "beta = -u left, +u right, u = 15 deg log-chirp(0.3->5 Hz), 1 s fades; attitude hold on";
    p.select_excitation =
        "beta = -u left, +u right, u = 17.5 deg linear chirp(0.25->4.5 Hz), 1 s fades; attitude "
        "hold on";
    v.push_back(p);
  }
  // The held vehicle: the same runs, identified from the excitation before the hold adds its
  // correction (the model then includes the hold). Yaw and vertical velocity have no such
  // variant: the hold acts on neither channel, so their excitation is what the wings did.
  for (const char* base : {"roll", "pitch"}) {
    ExperimentPreset p = *std::find_if(
        v.begin(), v.end(), [base](const ExperimentPreset& q) { return q.name == base; });
    p.name += "_held";
    p.input_columns = {std::string("u_") + base + "_rad"};
    p.held_vehicle = true;
    p.description = std::string("HELD VEHICLE (closed loop, attitude hold inside the model): ") +
                    base + " from the excitation before the hold; runs as " + base;
    v.push_back(p);
  }
  // Beyond the paper: experiments where the physics is nonlinear (docs/identifier.md §11).
  {
    ExperimentPreset p = BeyondPaper(
        Attitude("vertical_wide", "vz_mps_avg", "u_vertical_applied_rad", 0.5, "-", 0, kNotInPaper),
        1, 3, 5);
    p.input_columns = {"u_freq_hz", "u_vertical_applied_rad"};
    p.description =
        "beat-averaged vertical velocity over a wide operating range: f and phi0 of all four "
        "wings held at random levels (lift ~ f^2 phi0^2, damping depends on the climb rate)";
    p.train_excitation =
        "all wings: f in 4.6-6.6 Hz and phi0 in 38-84 deg, APRBS levels held 0.3-2 s (one stream "
        "each); 1 s fade from trim; attitude hold on";
    p.select_excitation = "as training, levels held 0.25-1.6 s, other streams";
    p.validate_excitation =
        "a different family: f = 5.6 + 0.95 log-chirp(0.02->0.6 Hz) Hz, phi0 = 61 + 21.9 deg "
        "log-chirp(0.03->1 Hz); 1 s fade from trim; attitude hold on";
    v.push_back(p);
  }
  {
    ExperimentPreset p =
        BeyondPaper(Actuator("force_map_fz", "fz_total_n_avg",
                             {"w1_freq_hz", "w1_amp_rad", "w1_beta_rad"}, 0.5, "-", 0, kNotInPaper),
                    0, 1, 25);
    p.description =
        "static map (f, phi0, beta) -> beat-averaged total vertical force on the test stand: "
        "levels held 0.25 s (longer than a beat), one row per level";
    p.train_excitation =
        "all wings: f in 4.5-7.5 Hz, phi0 in 25-84.9 deg, beta in -25..25 deg, independent "
        "uniform levels, each held 25 samples";
    p.select_excitation = "as training, other streams";
    p.validate_excitation =
        "a different family: levels sampled every 25 samples from slow log-chirps over the same "
        "ranges (f 0.01->0.5 Hz, phi0 0.02->1.2 Hz, beta 0.015->0.8 Hz)";
    v.push_back(p);
  }
  {
    ExperimentPreset p = BeyondPaper(
        Attitude("roll_coupled", "roll_rad", "u_roll_applied_rad", 0.5, "-", 0, kNotInPaper), 1, 8,
        3);
    p.input_columns = {"u_roll_applied_rad", "vy_mps_avg"};
    p.description =
        "roll with the coupled lateral state: inputs the applied left/right phi0 differential "
        "and the beat-averaged side velocity v_y (open loop, hold included)";
    p.train_excitation =
        "phi0 = trim +/- u (left +, right -), u = 6 deg (0.6 APRBS held 0.15-1 s, smoothed "
        "0.1 s + 0.4 linear chirp(0.1->3 Hz)), 1 s fades; attitude hold on";
    p.select_excitation =
        "as training, u = 5 deg, APRBS held 0.12-0.8 s (other stream), chirp(0.12->3.5 Hz)";
    p.validate_excitation =
        "a different family: u = 4.5 deg (0.5 log-chirp(0.15->4 Hz) + 0.5 multisine of 12 "
        "tones 0.07-2.5 Hz, random phases), 1 s fades; attitude hold on";
    v.push_back(p);
  }
  // The damage scenarios: one stationary excitation family in all three phases (so accuracy
  // before and after the change is comparable), the vehicle changing halfway through the
  // validation run.
  {
    ExperimentPreset p = BeyondPaper(
        Actuator("wing_damage", "fz1_n", {"w1_freq_hz", "w1_amp_rad"}, 0.5, "-", 0, kNotInPaper), 2,
        2, 1);
    p.description =
        "DAMAGE: wing 1's vertical force on the test stand; halfway through the validation run "
        "wing 1 loses 30 % of its stroke amplitude (it still receives the full command)";
    p.select_duration_s = 30.0;
    p.validate_damage.at_s = 30.0;
    p.validate_damage.wing = 1;
    p.validate_damage.amplitude_scale = 0.7;
    p.train_excitation =
        "all wings: f in 5-7 Hz and phi0 in 35-80 deg, APRBS levels held 0.3-1 s (one stream "
        "each)";
    p.select_excitation = "as training, other streams";
    p.validate_excitation = "as training, other streams; from 30 s wing 1 flies 0.7 phi0";
    v.push_back(p);
  }
  {
    ExperimentPreset p = *std::find_if(
        v.begin(), v.end(), [](const ExperimentPreset& q) { return q.name == "vertical_wide"; });
    p.name = "battery_sag";
    p.description =
        "DAMAGE: beat-averaged vertical velocity in free flight; halfway through the validation "
        "run every wing's flapping frequency sags to 90 % of the command (a tired battery)";
    p.select_duration_s = 30.0;
    p.validate_damage.at_s = 30.0;
    p.validate_damage.wing = 0;
    p.validate_damage.frequency_scale = 0.9;
    p.train_excitation = "as vertical_wide training (APRBS f and phi0, hold on)";
    p.select_excitation = "as vertical_wide selection";
    p.validate_excitation =
        "as vertical_wide selection, other streams; from 30 s all wings flap at 0.9 f";
    v.push_back(p);
  }
  return v;
}

}  // namespace

const std::vector<ExperimentPreset>& Presets() {
  static const std::vector<ExperimentPreset> kPresets = MakePresets();
  return kPresets;
}

const ExperimentPreset* FindPreset(const std::string& name) {
  for (const ExperimentPreset& p : Presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

std::string PresetNames() {
  std::string names;
  for (const ExperimentPreset& p : Presets()) names += (names.empty() ? "" : ", ") + p.name;
  return names;
}

const char* PhaseName(Phase phase) {
  switch (phase) {
    case Phase::kTrain:
      return "train";
    case Phase::kSelect:
      return "select";
    case Phase::kValidate:
      break;
  }
  return "validate";
}

std::optional<Phase> ParsePhase(const std::string& name) {
  for (const Phase phase : {Phase::kTrain, Phase::kSelect, Phase::kValidate}) {
    if (name == PhaseName(phase)) return phase;
  }
  return std::nullopt;
}

const std::vector<std::string>& PhaseNames() {
  static const std::vector<std::string> kNames = {"train", "select", "validate"};
  return kNames;
}

double PhaseDurationS(const ExperimentPreset& preset, Phase phase) {
  switch (phase) {
    case Phase::kTrain:
      return preset.train_duration_s;
    case Phase::kSelect:
      return preset.select_duration_s;
    case Phase::kValidate:
      break;
  }
  return preset.validate_duration_s;
}

double VerticalChannelRad(const CommandMatrix& c, double trim_amp_rad) {
  return 0.5 * (PairMean(c, kLeft, kStrokeAmplitude) + PairMean(c, kRight, kStrokeAmplitude)) -
         trim_amp_rad;
}

double RollChannelRad(const CommandMatrix& c) {
  return 0.5 * (PairMean(c, kLeft, kStrokeAmplitude) - PairMean(c, kRight, kStrokeAmplitude));
}

double PitchChannelRad(const CommandMatrix& c) {
  return 0.5 * (PairMean(c, kFront, kStrokeAmplitude) - PairMean(c, kBack, kStrokeAmplitude));
}

double YawChannelRad(const CommandMatrix& c) {
  return 0.5 * (PairMean(c, kRight, kStrokePlaneAngle) - PairMean(c, kLeft, kStrokePlaneAngle));
}

const std::vector<std::string>& AppliedChannelNames() {
  static const std::vector<std::string> kNames = {"u_vertical_applied_rad", "u_roll_applied_rad",
                                                  "u_pitch_applied_rad", "u_yaw_applied_rad"};
  return kNames;
}

std::vector<double> AppliedChannelValues(const CommandMatrix& applied, double trim_amp_rad) {
  return {VerticalChannelRad(applied, trim_amp_rad), RollChannelRad(applied),
          PitchChannelRad(applied), YawChannelRad(applied)};
}

ExperimentRun BuildExperimentRun(const ExperimentPreset& preset, Phase phase, std::uint64_t seed,
                                 double duration_s, const plant::PlantConfig& config) {
  const plant::TrimResult trim = plant::FindHoverTrim(config);
  const double dt_s = 1.0 / config.integration.sample_rate_hz;
  const double t_end_s = duration_s > 0.0 ? duration_s : PhaseDurationS(preset, phase);
  const std::size_t samples = static_cast<std::size_t>(std::llround(t_end_s / dt_s));
  const double a0 = trim.amp_rad;
  const double phase0 = RandomPhaseRad(seed, phase, 1);
  const double phase1 = RandomPhaseRad(seed, phase, 2);
  const double phase2 = RandomPhaseRad(seed, phase, 3);
  // A held-vehicle variant flies exactly the runs of the preset it varies.
  std::string name = preset.name;
  if (preset.held_vehicle) name.resize(name.size() - std::string("_held").size());

  Builder b{config, trim, {}};
  b.run.trim = trim;
  b.run.sample_period_s = dt_s;
  b.run.initial.prior_command = trim.command;
  b.run.initial.clamped_body = preset.clamped_body;
  b.run.attitude_hold = preset.attitude_hold;
  b.run.record_applied = preset.attitude_hold;
  b.run.hold_gains = DefaultAttitudeHoldGains();
  b.run.initial.state.position_m = Eigen::Vector3d(0.0, 0.0, preset.start_altitude_m);

  const auto fade = [&](double t) { return signals::TukeyEnvelope(t, t_end_s, kRampS); };

  if (name == "actuator_fz" || name == "actuator_fx") {
    const bool with_beta = name == "actuator_fx";
    // The slow frequency sweep and the faster amplitude sweep of the paper's Fig. 4 and 6.
    const signals::LinearChirp f_train(0.02, 0.5, 0.5, t_end_s, phase0);
    const signals::LinearChirp f_select(0.025, 0.65, 0.75, t_end_s, phase0);
    const signals::LogChirp f_val(0.03, 0.8, 1.0, t_end_s, phase0);
    const signals::LinearChirp a_train(0.05, 5.0, 30.0 * kRadPerDeg, t_end_s, phase1);
    const signals::LinearChirp a_select(0.07, 6.5, 28.0 * kRadPerDeg, t_end_s, phase1);
    const signals::LogChirp a_val(0.1, 8.0, 25.0 * kRadPerDeg, t_end_s, phase1);
    const signals::LinearChirp beta_train(0.02, 1.0, 10.0 * kRadPerDeg, t_end_s, phase2);
    const signals::LinearChirp beta_select(0.025, 1.5, 9.0 * kRadPerDeg, t_end_s, phase2);
    const signals::LogChirp beta_val(0.03, 2.0, 8.0 * kRadPerDeg, t_end_s, phase2);
    b.Fill(
        samples, dt_s,
        [&](double t, CommandMatrix* c) {
          const double f = 6.0 + ByPhase(phase, f_train, f_select, f_val, t);
          const double a = 50.0 * kRadPerDeg + ByPhase(phase, a_train, a_select, a_val, t);
          c->col(kFlapFrequency).setConstant(f);
          c->col(kStrokeAmplitude).setConstant(a);
          if (with_beta) {
            c->col(kStrokePlaneAngle)
                .setConstant(ByPhase(phase, beta_train, beta_select, beta_val, t));
          }
        },
        nullptr, "");
    return b.run;
  }

  if (name == "vertical_velocity") {
    // φ₀ ≈ 1.03 rad at the centre, 1.48 rad (85°) at the limit: the chirp and the noise, cut at
    // ±2.5σ (0.26 rad at 0.01 W), must share the 0.45 rad between.
    const double amplitude_rad =
        phase == Phase::kTrain ? 0.19 : (phase == Phase::kSelect ? 0.18 : 0.17);
    // Lift ∝ φ₀²: centring on φ₀c = √(φ₀² − E[u²]) keeps the mean lift at the weight.
    const double mean_square = 0.5 * amplitude_rad * amplitude_rad + kNoisePowerW;
    const double centre_rad = std::sqrt(a0 * a0 - mean_square);
    const signals::LinearChirp c_train(0.05, 5.0, amplitude_rad, t_end_s, phase0);
    const signals::LinearChirp c_select(0.06, 5.5, amplitude_rad, t_end_s, phase0);
    const signals::LogChirp c_val(0.05, 6.0, amplitude_rad, t_end_s, phase0);
    signals::GaussianNoise noise(kNoisePowerW, NoiseSeed(seed, phase), kNoiseClipSigmas);
    b.Fill(
        samples, dt_s,
        [&](double t, CommandMatrix* c) {
          const double u = ByPhase(phase, c_train, c_select, c_val, t) + noise.Next();
          c->col(kStrokeAmplitude).setConstant(centre_rad + u);
        },
        [&](const CommandMatrix& c) { return VerticalChannelRad(c, a0); }, "u_vertical_rad");
    return b.run;
  }

  if (name == "roll" || name == "pitch") {
    // Bands stay well below the wing beat (≈ 5.4 Hz): a φ₀ modulation near f beats with the
    // stroke's odd harmonics and rectifies into a steady moment the wing-beat-mean model cannot
    // represent (it tumbled the vehicle in simulation).
    const bool roll = name == "roll";
    const double train_deg = roll ? 3.0 : 1.0, select_deg = roll ? 4.0 : 1.25,
                 val_deg = roll ? 5.0 : 1.5;
    const double amplitude_rad =
        (phase == Phase::kTrain ? train_deg : (phase == Phase::kSelect ? select_deg : val_deg)) *
        kRadPerDeg;
    const signals::LinearChirp c_train(0.1, 3.0, amplitude_rad, t_end_s, phase0);
    const signals::LinearChirp c_select(0.12, 3.5, amplitude_rad, t_end_s, phase0);
    const signals::LogChirp c_val(0.15, 4.0, amplitude_rad, t_end_s, phase0);
    const int* plus = roll ? kLeft : kFront;
    const int* minus = roll ? kRight : kBack;
    b.Fill(
        samples, dt_s,
        [&](double t, CommandMatrix* c) {
          const double u = fade(t) * ByPhase(phase, c_train, c_select, c_val, t);
          for (int i = 0; i < 2; ++i) {
            (*c)(plus[i], kStrokeAmplitude) = a0 + u;
            (*c)(minus[i], kStrokeAmplitude) = a0 - u;
          }
        },
        [roll](const CommandMatrix& c) { return roll ? RollChannelRad(c) : PitchChannelRad(c); },
        roll ? "u_roll_rad" : "u_pitch_rad");
    return b.run;
  }

  if (name == "yaw") {
    const double amplitude_rad =
        (phase == Phase::kTrain ? 20.0 : (phase == Phase::kSelect ? 17.5 : 15.0)) * kRadPerDeg;
    const signals::LinearChirp c_train(0.2, 4.0, amplitude_rad, t_end_s, phase0);
    const signals::LinearChirp c_select(0.25, 4.5, amplitude_rad, t_end_s, phase0);
    const signals::LogChirp c_val(0.3, 5.0, amplitude_rad, t_end_s, phase0);
    b.Fill(
        samples, dt_s,
        [&](double t, CommandMatrix* c) {
          const double u = fade(t) * ByPhase(phase, c_train, c_select, c_val, t);
          for (int i = 0; i < 2; ++i) {
            (*c)(kLeft[i], kStrokePlaneAngle) = -u;
            (*c)(kRight[i], kStrokePlaneAngle) = u;
          }
        },
        YawChannelRad, "u_yaw_rad");
    return b.run;
  }
  if (phase == Phase::kValidate) b.run.damage = preset.validate_damage;

  if (name == "wing_damage") {
    const int hold_min = 30, hold_max = 100;
    const std::vector<double> f =
        signals::AprbsSequence(samples, {5.0, 7.0, hold_min, hold_max}, AprbsSeed(seed, phase, 30));
    const std::vector<double> a =
        signals::AprbsSequence(samples, {35.0 * kRadPerDeg, 80.0 * kRadPerDeg, hold_min, hold_max},
                               AprbsSeed(seed, phase, 32));
    b.Fill(
        samples, dt_s,
        [&](double t, CommandMatrix* c) {
          const std::size_t k = static_cast<std::size_t>(std::llround(t / dt_s));
          c->col(kFlapFrequency).setConstant(f[k]);
          c->col(kStrokeAmplitude).setConstant(a[k]);
        },
        nullptr, "");
    return b.run;
  }

  if (name == "vertical_wide" || name == "battery_sag") {
    // Ranges inside the limits (f ≤ 8 Hz, φ₀ ≤ 85°) with room for the hold's φ₀ differential.
    constexpr double kFLow = 4.6, kFHigh = 6.6;
    constexpr double kALow = 38.0 * kRadPerDeg, kAHigh = 84.0 * kRadPerDeg;
    std::vector<double> f, a;
    if (phase == Phase::kValidate && name == "vertical_wide") {
      const signals::LogChirp f_chirp(0.02, 0.6, 0.95 * 0.5 * (kFHigh - kFLow), t_end_s, phase0);
      const signals::LogChirp a_chirp(0.03, 1.0, 0.95 * 0.5 * (kAHigh - kALow), t_end_s, phase1);
      for (std::size_t k = 0; k < samples; ++k) {
        const double t = static_cast<double>(k) * dt_s;
        f.push_back(0.5 * (kFLow + kFHigh) + f_chirp.Value(t));
        a.push_back(0.5 * (kALow + kAHigh) + a_chirp.Value(t));
      }
    } else {
      const bool train = phase == Phase::kTrain;
      const int hold_min = train ? 30 : 25, hold_max = train ? 200 : 160;
      f = signals::AprbsSequence(samples, {kFLow, kFHigh, hold_min, hold_max},
                                 AprbsSeed(seed, phase, 1));
      a = signals::AprbsSequence(samples, {kALow, kAHigh, hold_min, hold_max},
                                 AprbsSeed(seed, phase, 2));
    }
    b.Fill(
        samples, dt_s,
        [&](double t, CommandMatrix* c) {
          // Fade in from hover trim over kRampS so every run starts in the air at rest.
          const std::size_t k = static_cast<std::size_t>(std::llround(t / dt_s));
          const double w = std::min(1.0, t / kRampS);
          c->col(kFlapFrequency).setConstant(trim.freq_hz + w * (f[k] - trim.freq_hz));
          c->col(kStrokeAmplitude).setConstant(a0 + w * (a[k] - a0));
        },
        [&](const CommandMatrix& c) { return VerticalChannelRad(c, a0); }, "u_vertical_rad");
    b.AddExcitation("u_freq_hz", MeanFrequencyHz);
    return b.run;
  }

  if (name == "force_map_fz") {
    // Levels change only at multiples of the decimation block, so each decimated row's input is
    // one level and the next row's output its settled beat mean: y(j + 1) = g(u(j)).
    const int block = preset.decimate;
    const double lows[3] = {4.5, 25.0 * kRadPerDeg, -25.0 * kRadPerDeg};
    const double highs[3] = {7.5, 84.9 * kRadPerDeg, 25.0 * kRadPerDeg};
    const double bands[3][2] = {{0.01, 0.5}, {0.02, 1.2}, {0.015, 0.8}};
    std::vector<double> level[3];
    for (int i = 0; i < 3; ++i) {
      if (phase == Phase::kValidate) {
        const signals::LogChirp chirp(bands[i][0], bands[i][1], 0.5 * (highs[i] - lows[i]), t_end_s,
                                      RandomPhaseRad(seed, phase, 10 + i));
        for (std::size_t k = 0; k < samples; ++k) {
          const std::size_t start = k - k % static_cast<std::size_t>(block);
          level[i].push_back(0.5 * (lows[i] + highs[i]) +
                             chirp.Value(static_cast<double>(start) * dt_s));
        }
      } else {
        level[i] = signals::AprbsSequence(samples, {lows[i], highs[i], block, block},
                                          AprbsSeed(seed, phase, 10 + i));
      }
    }
    b.Fill(
        samples, dt_s,
        [&](double t, CommandMatrix* c) {
          const std::size_t k = static_cast<std::size_t>(std::llround(t / dt_s));
          c->col(kFlapFrequency).setConstant(level[0][k]);
          c->col(kStrokeAmplitude).setConstant(level[1][k]);
          c->col(kStrokePlaneAngle).setConstant(level[2][k]);
        },
        nullptr, "");
    return b.run;
  }

  if (name == "roll_coupled") {
    std::vector<double> u(samples);
    if (phase == Phase::kValidate) {
      // A different family from training's: a log chirp plus a multisine, no held levels.
      std::mt19937_64 rng = Stream(seed, phase, 20);
      std::vector<double> freqs, amps, phases;
      for (int i = 0; i < 12; ++i) {
        freqs.push_back(0.07 + (2.5 - 0.07) * i / 11.0);
        amps.push_back(1.0);
        phases.push_back(2.0 * kPi * static_cast<double>(rng() >> 11) * 0x1.0p-53);
      }
      const signals::Multisine tones(freqs, amps, phases);
      const signals::LogChirp chirp(0.15, 4.0, 1.0, t_end_s, phase0);
      double peak = 0.0;
      for (std::size_t k = 0; k < samples; ++k)
        peak = std::max(peak, std::abs(tones.Value(static_cast<double>(k) * dt_s)));
      const double amplitude_rad = 4.5 * kRadPerDeg;
      for (std::size_t k = 0; k < samples; ++k) {
        const double t = static_cast<double>(k) * dt_s;
        u[k] = amplitude_rad * (0.5 * chirp.Value(t) + 0.5 * tones.Value(t) / peak);
      }
    } else {
      const bool train = phase == Phase::kTrain;
      const double amplitude_rad = (train ? 6.0 : 5.0) * kRadPerDeg;
      const std::vector<double> levels = signals::AprbsSequence(
          samples, {-1.0, 1.0, train ? 15 : 12, train ? 100 : 80, 10}, AprbsSeed(seed, phase, 20));
      const signals::LinearChirp chirp(train ? 0.1 : 0.12, train ? 3.0 : 3.5, 1.0, t_end_s, phase0);
      for (std::size_t k = 0; k < samples; ++k) {
        u[k] = amplitude_rad * (0.6 * levels[k] + 0.4 * chirp.Value(static_cast<double>(k) * dt_s));
      }
    }
    b.Fill(
        samples, dt_s,
        [&](double t, CommandMatrix* c) {
          const std::size_t k = static_cast<std::size_t>(std::llround(t / dt_s));
          const double uk = fade(t) * u[k];
          for (int i = 0; i < 2; ++i) {
            (*c)(kLeft[i], kStrokeAmplitude) = a0 + uk;
            (*c)(kRight[i], kStrokeAmplitude) = a0 - uk;
          }
        },
        RollChannelRad, "u_roll_rad");
    return b.run;
  }

  throw std::runtime_error("BuildExperimentRun: no excitation defined for preset " + preset.name);
}

}  // namespace odonata::experiments
