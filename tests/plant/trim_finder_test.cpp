#include "plant/trim_finder.hpp"

#include <gtest/gtest.h>

#include "plant/dimav_plant.hpp"

namespace odonata::plant {
namespace {

TEST(TrimFinder, HoverTrimIsBetweenFiveAndSixHertz) {
  const TrimResult t = FindHoverTrim(DefaultPlantConfig());
  EXPECT_GT(t.freq_hz, 5.0);
  EXPECT_LT(t.freq_hz, 6.0);
  EXPECT_NEAR(t.mean_load.force_n.z(), 0.04 * 9.81, 1e-9);
  EXPECT_LT(t.mean_load.moment_nm.norm(), 1e-12);
  EXPECT_LT(std::fabs(t.mean_load.force_n.x()), 1e-12);
}

// docs/plant.md §9: from translational forces alone, hover at ≈ 5.36 Hz with 0.098 N per wing.
TEST(TrimFinder, TranslationalOnlyHoverMatchesPlantMd) {
  PlantConfig c = DefaultPlantConfig();
  c.integration.rotational_forces = false;
  const TrimResult t = FindHoverTrim(c);
  EXPECT_NEAR(t.freq_hz, 5.36, 0.01);
  EXPECT_NEAR(t.mean_load.wing_force_z_n(0), 0.098, 0.001);
  // With Δφ = 0 the rotational force is antisymmetric in each half-stroke: same trim.
  EXPECT_NEAR(FindHoverTrim(DefaultPlantConfig()).freq_hz, t.freq_hz, 1e-6);
}

TEST(TrimFinder, AmplitudeTrimAtFixedFrequency) {
  PlantConfig c = DefaultPlantConfig();
  c.nominal_command(kFlapFrequency) = 6.0;
  TrimOptions o;
  o.variable = TrimVariable::kAmplitude;
  const TrimResult t = FindHoverTrim(c, o);
  EXPECT_LT(t.amp_rad, c.nominal_command(kStrokeAmplitude));  // faster flapping, less amplitude
  EXPECT_NEAR(t.mean_load.force_n.z(), 0.04 * 9.81, 1e-9);
}

// Released at trim in free flight, the vehicle stays put (wing-beat oscillation only).
TEST(TrimFinder, TrimHoldsAltitudeInFreeFlight) {
  const PlantConfig c = DefaultPlantConfig();
  const TrimResult t = FindHoverTrim(c);
  DimavPlant plant(c);
  InitialCondition ic;
  ic.state.position_m.z() = 10.0;
  ic.prior_command = t.command;
  plant.Reset(ic);
  for (int k = 0; k < 200; ++k) ASSERT_EQ(plant.Step(t.command), StepStatus::kOk);
  EXPECT_NEAR(plant.output().position_m.z(), 10.0, 0.05);
  EXPECT_LT(plant.output().velocity_body_mps.norm(), 0.3);
}

}  // namespace
}  // namespace odonata::plant
