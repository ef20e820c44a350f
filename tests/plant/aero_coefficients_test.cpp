#include "plant/aero_coefficients.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "plant/angle_constants.hpp"

namespace odonata::plant {
namespace {

// docs/plant.md §3 check points, quoted to two decimals.
TEST(AeroCoefficients, MatchesPlantMdCheckPoints) {
  EXPECT_NEAR(LiftCoefficient(45.0 * kRadPerDeg), 1.80, 0.005);
  EXPECT_NEAR(DragCoefficient(45.0 * kRadPerDeg), 1.70, 0.005);
  EXPECT_NEAR(DragCoefficient(90.0 * kRadPerDeg), 3.46, 0.005);
  EXPECT_DOUBLE_EQ(RotationalForceCoefficient(0.25), kPi / 2.0);
}

// The fast table must be indistinguishable from the formulas (< 1e-9 absolute) over α ∈ [0, 90°].
TEST(AeroCoefficientTable, MatchesExactCoefficients) {
  const AeroCoefficientTable table;
  double worst = 0.0;
  for (int i = 0; i <= 100000; ++i) {
    const double u = i / 100000.0;
    const double alpha = AeroCoefficientTable::AlphaFromRatio(u);
    double cl, cd;
    table.Evaluate(u, &cl, &cd);
    worst = std::max(
        {worst, std::fabs(cl - LiftCoefficient(alpha)), std::fabs(cd - DragCoefficient(alpha))});
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(AeroCoefficientTable, RatioMapsToAcuteAngle) {
  EXPECT_DOUBLE_EQ(AeroCoefficientTable::AlphaFromRatio(0.0), 0.0);
  EXPECT_NEAR(AeroCoefficientTable::AlphaFromRatio(0.5), kPi / 4.0, 1e-15);
  EXPECT_NEAR(AeroCoefficientTable::AlphaFromRatio(1.0), kPi / 2.0, 1e-15);
}

}  // namespace
}  // namespace odonata::plant
