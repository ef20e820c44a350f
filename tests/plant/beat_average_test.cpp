// DimavPlant's beat averages (PlantOutput::beat): trailing means over the last wing beat.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "plant/dimav_plant.hpp"
#include "plant/trim_finder.hpp"

namespace odonata::plant {
namespace {

double AngleGap(double a_rad, double b_rad) {
  return std::fabs(std::remainder(a_rad - b_rad, 2 * M_PI));
}

InitialCondition HoverStart(const TrimResult& t) {
  InitialCondition ic;
  ic.state.position_m.z() = 50.0;
  ic.prior_command = t.command;
  return ic;
}

// Right after a reset the history is the initial state (the wings primed with the prior
// command): the averages are that state, and the total forces the per-wing means summed.
TEST(BeatAverages, StartAtTheInitialState) {
  const PlantConfig c = DefaultPlantConfig();
  const TrimResult t = FindHoverTrim(c);
  DimavPlant plant(c);
  InitialCondition ic = HoverStart(t);
  ic.state.velocity_body_mps = Eigen::Vector3d(0.1, -0.2, 0.3);
  ic.state.rate_body_radps = Eigen::Vector3d(0.4, -0.5, 0.6);
  ic.state.attitude = QuaternionFromRollPitchYaw(0.1, -0.2, 3.0);
  plant.Reset(ic);
  const PlantOutput& o = plant.output();
  EXPECT_NEAR(o.beat.window_s, 1.0 / t.command(0, kFlapFrequency), 1e-12);
  EXPECT_LT((o.beat.velocity_body_mps - o.velocity_body_mps).norm(), 1e-12);
  EXPECT_LT((o.beat.rate_body_radps - o.rate_body_radps).norm(), 1e-12);
  EXPECT_NEAR(o.beat.roll_rad, o.roll_rad, 1e-12);
  EXPECT_NEAR(o.beat.pitch_rad, o.pitch_rad, 1e-12);
  EXPECT_NEAR(o.beat.yaw_rad, o.yaw_rad, 1e-12);
  EXPECT_NEAR(o.beat.force_x_n, o.force_x_n.sum(), 1e-12);
  EXPECT_NEAR(o.beat.force_z_n, o.force_z_n.sum(), 1e-12);
}

// At hover the raw body velocity ripples at the wing beat; the beat average does not, and its
// total vertical force is the weight.
TEST(BeatAverages, RemoveTheWingBeatRippleAtHover) {
  const PlantConfig c = DefaultPlantConfig();
  const TrimResult t = FindHoverTrim(c);
  DimavPlant plant(c);
  plant.Reset(HoverStart(t));
  std::vector<double> raw, avg;
  for (int k = 0; k < 200; ++k) {
    ASSERT_EQ(plant.Step(t.command), StepStatus::kOk);
    const PlantOutput& o = plant.output();
    if (k >= 50) {
      raw.push_back(o.velocity_body_mps.z());
      avg.push_back(o.beat.velocity_body_mps.z());
      // All four wings flap at the same f: the total is the per-wing means summed.
      EXPECT_NEAR(o.beat.force_z_n, o.force_z_n.sum(), 1e-9);
      EXPECT_NEAR(o.beat.force_x_n, o.force_x_n.sum(), 1e-9);
    }
  }
  const auto spread = [](const std::vector<double>& v) {
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *hi - *lo;
  };
  // Detrended spread over the last 1.5 s: the drift of an open-loop hover is slow, the ripple
  // is not.
  std::vector<double> raw_hp(raw.size()), avg_hp(avg.size());
  for (std::size_t k = 1; k < raw.size(); ++k) {
    raw_hp[k] = raw[k] - raw[k - 1];
    avg_hp[k] = avg[k] - avg[k - 1];
  }
  EXPECT_GT(spread(raw_hp), 0.02);  // the ripple is there …
  EXPECT_LT(spread(avg_hp), 0.1 * spread(raw_hp)) << spread(avg_hp) << " vs " << spread(raw_hp);
  const double weight_n = c.mass_kg * c.gravity_mps2;
  EXPECT_NEAR(plant.output().beat.force_z_n / weight_n, 1.0, 0.05);
}

// With one integration step per sample every step is an output, so the averages can be checked
// against a brute-force trailing mean of the outputs (the history before t = 0 being the initial
// state). Upside down and spinning, roll crosses ±π and yaw keeps unwrapping: the means are of
// the continuous angles.
TEST(BeatAverages, EqualABruteForceMeanOfContinuousAngles) {
  PlantConfig c = DefaultPlantConfig();
  c.integration.sample_rate_hz = c.integration.min_steps_per_beat * c.limits.max(kFlapFrequency);
  c.divergence.max_tilt_rad = 10.0;  // flying upside down on purpose
  const TrimResult t = FindHoverTrim(c);
  DimavPlant plant(c);
  ASSERT_EQ(plant.steps_per_sample(), 1);
  InitialCondition ic = HoverStart(t);
  ic.state.attitude = QuaternionFromRollPitchYaw(M_PI - 0.05, 0.0, -M_PI + 0.03);
  ic.state.rate_body_radps = Eigen::Vector3d(3.0, 0.0, 2.5);
  plant.Reset(ic);

  const double step_s = plant.step_s();
  const double window_s = 1.0 / t.command(0, kFlapFrequency);
  const double steps = window_s / step_s;
  const int full = static_cast<int>(steps);
  const double fraction = steps - full;
  struct Row {
    Eigen::Vector3d v, w;
    double roll, pitch, yaw;
  };
  const auto row_of = [](const PlantOutput& o, double roll_continuous) {
    return Row{o.velocity_body_mps, o.rate_body_radps, roll_continuous, o.pitch_rad, o.yaw_rad};
  };
  std::vector<Row> history(400, row_of(plant.output(), plant.output().roll_rad));  // primed
  double roll = plant.output().roll_rad;
  bool crossed = false;
  for (int k = 0; k < 300; ++k) {
    ASSERT_EQ(plant.Step(t.command), StepStatus::kOk) << plant.divergence_message();
    const PlantOutput& o = plant.output();
    roll += std::remainder(o.roll_rad - std::remainder(roll, 2 * M_PI), 2 * M_PI);
    history.push_back(row_of(o, roll));
    crossed = crossed || o.roll_rad < 0.0;

    Row sum{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0, 0.0, 0.0};
    const auto add = [&sum](const Row& r, double weight) {
      sum.v += weight * r.v;
      sum.w += weight * r.w;
      sum.roll += weight * r.roll;
      sum.pitch += weight * r.pitch;
      sum.yaw += weight * r.yaw;
    };
    for (int j = 0; j < full; ++j) add(history[history.size() - 1 - j], 1.0);
    add(history[history.size() - 1 - full], fraction);
    const double n = full + fraction;
    ASSERT_LT((o.beat.velocity_body_mps - sum.v / n).norm(), 1e-9) << k;
    ASSERT_LT((o.beat.rate_body_radps - sum.w / n).norm(), 1e-9) << k;
    ASSERT_LT(AngleGap(o.beat.roll_rad, sum.roll / n), 1e-9) << k;
    ASSERT_GT(o.beat.roll_rad, -M_PI);
    ASSERT_LE(o.beat.roll_rad, M_PI);
    ASSERT_NEAR(o.beat.pitch_rad, sum.pitch / n, 1e-9) << k;
    ASSERT_NEAR(o.beat.yaw_rad, sum.yaw / n, 1e-9) << k;  // unwrapped, like yaw_rad
  }
  EXPECT_TRUE(crossed);  // roll did cross ±π …
  // … and yaw went past −π without wrapping (upside down, body r > 0 turns the world yaw down).
  EXPECT_LT(plant.output().yaw_rad, -M_PI - 0.05);
}

}  // namespace
}  // namespace odonata::plant
