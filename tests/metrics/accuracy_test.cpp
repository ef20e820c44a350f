#include <cmath>

#include <gtest/gtest.h>

#include "metrics/accuracy.hpp"

namespace odonata::metrics {
namespace {

TEST(Accuracy, KnownAnswers) {
  Eigen::VectorXd y(4), yh(4);
  y << 1, 2, 3, 4;
  yh << 1, 2, 3, 4;
  EXPECT_DOUBLE_EQ(Score(y, yh).fit_percent, 100.0);
  yh = Eigen::VectorXd::Constant(4, 2.5);  // the mean: FIT 0, VAF 0
  EXPECT_NEAR(Score(y, yh).fit_percent, 0.0, 1e-12);
  EXPECT_NEAR(Score(y, yh).vaf_percent, 0.0, 1e-12);
  yh << 1.5, 2.5, 3.5, 4.5;  // a constant offset: VAF ignores it, FIT does not
  const Accuracy a = Score(y, yh);
  EXPECT_NEAR(a.vaf_percent, 100.0, 1e-12);
  EXPECT_NEAR(a.rmse, 0.5, 1e-12);
  const double std_y = std::sqrt(1.25);
  EXPECT_NEAR(a.ndei, 0.5 / std_y, 1e-12);
  EXPECT_NEAR(a.fit_percent, 100 * (1 - a.ndei), 1e-9);  // FIT = 1 − NDEI
}

TEST(Accuracy, ConstantMeasuredSignal) {
  const Eigen::VectorXd y = Eigen::VectorXd::Ones(3);
  EXPECT_EQ(Score(y, y).fit_percent, 100.0);
  EXPECT_TRUE(std::isinf(Score(y, Eigen::VectorXd::Zero(3)).fit_percent));
}

}  // namespace
}  // namespace odonata::metrics

#include "metrics/running_accuracy.hpp"

namespace odonata::metrics {
namespace {

TEST(RunningAccuracy, CumulativeAndWindowAgreeWithTheBatchScore) {
  Eigen::VectorXd y(200), p(200);
  for (int k = 0; k < 200; ++k) {
    y(k) = std::sin(0.1 * k) + 3.0;
    p(k) = y(k) + 0.05 * std::cos(0.37 * k) + 0.01;
  }
  CumulativeAccuracy total;
  WindowAccuracy window(50);
  for (int k = 0; k < 200; ++k) {
    total.Add(y(k), p(k));
    window.Add(y(k), p(k));
  }
  const Accuracy batch = Score(y, p);
  EXPECT_NEAR(total.Get().fit_percent, batch.fit_percent, 1e-9);
  EXPECT_NEAR(total.Get().vaf_percent, batch.vaf_percent, 1e-9);
  EXPECT_NEAR(total.Get().rmse, batch.rmse, 1e-12);
  const Accuracy last = Score(y.tail(50), p.tail(50));
  EXPECT_TRUE(window.full());
  EXPECT_NEAR(window.Get().fit_percent, last.fit_percent, 1e-12);
  EXPECT_EQ(window.Get().samples, 50);
}

}  // namespace
}  // namespace odonata::metrics
