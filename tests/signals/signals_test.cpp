#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <set>
#include <vector>

#include "signals/chirp.hpp"
#include "signals/gaussian_noise.hpp"
#include "signals/multisine.hpp"
#include "signals/prbs.hpp"
#include "signals/step_signal.hpp"
#include "signals/taper.hpp"

namespace odonata::signals {
namespace {

// Counts upward zero crossings of f on [t0, t1] sampled at 100 kHz.
template <class F>
int UpCrossings(const F& f, double t0, double t1) {
  int n = 0;
  double prev = f(t0);
  for (double t = t0 + 1e-5; t <= t1; t += 1e-5) {
    const double x = f(t);
    if (prev < 0.0 && x >= 0.0) ++n;
    prev = x;
  }
  return n;
}

TEST(LinearChirp, SweepsFromStartToEndFrequency) {
  const LinearChirp c(1.0, 11.0, 2.0, 10.0);
  EXPECT_DOUBLE_EQ(c.FrequencyHz(5.0), 6.0);
  // Cycles in [0, 10] = ∫ f dt = 60.
  EXPECT_NEAR(UpCrossings([&](double t) { return c.Value(t); }, 0.0, 10.0), 60, 1);
  double peak = 0.0;
  for (double t = 0; t <= 10.0; t += 1e-4) peak = std::max(peak, std::fabs(c.Value(t)));
  EXPECT_NEAR(peak, 2.0, 1e-3);
  EXPECT_EQ(c.Value(-1.0), 0.0);
  EXPECT_EQ(c.Value(11.0), 0.0);
}

TEST(LogChirp, FrequencyGrowsGeometrically) {
  const LogChirp c(0.5, 8.0, 1.0, 8.0);
  EXPECT_NEAR(c.FrequencyHz(2.0), 1.0, 1e-12);  // one octave every 2 s
  EXPECT_NEAR(c.FrequencyHz(8.0), 8.0, 1e-12);
  // Cycles = f₀ T (k − 1) / ln k = 0.5·8·15/ln 16 ≈ 21.6.
  EXPECT_NEAR(UpCrossings([&](double t) { return c.Value(t); }, 0.0, 8.0), 21.6, 1.0);
}

TEST(Multisine, SumsItsComponents) {
  const Multisine m({1.0, 2.0}, {1.0, 0.5}, {0.0, M_PI / 2});
  EXPECT_NEAR(m.Value(0.1), std::sin(2 * M_PI * 0.1) + 0.5 * std::cos(2 * M_PI * 0.2), 1e-12);
  const Multisine s = Multisine::Schroeder({1, 2, 3, 4, 5}, 0.2);
  EXPECT_DOUBLE_EQ(s.PeakBound(), 1.0);
  for (double t = 0; t < 2.0; t += 1e-3) EXPECT_LE(std::fabs(s.Value(t)), 1.0 + 1e-12);
}

TEST(Prbs, HasMaximalPeriodAndIsBalanced) {
  for (const int order : {3, 5, 7, 10}) {
    Prbs p(order, 1, 1.0, 42);
    const std::size_t period = p.period_bits();
    const std::vector<double> x = p.Generate(2 * period);
    for (std::size_t i = 0; i < period; ++i) ASSERT_EQ(x[i], x[i + period]) << order;
    // A maximal-length sequence has one more +1 than −1 per period.
    const double sum = std::accumulate(x.begin(), x.begin() + period, 0.0);
    EXPECT_EQ(std::fabs(sum), 1.0) << order;
    // …and no shorter period.
    bool shorter = false;
    for (std::size_t q = 1; q < period && !shorter; ++q) {
      if (period % q) continue;
      bool same = true;
      for (std::size_t i = 0; i + q < period && same; ++i) same = x[i] == x[i + q];
      shorter = same;
    }
    EXPECT_FALSE(shorter) << order;
  }
}

TEST(Prbs, HoldsEachBitAndIsSeeded) {
  Prbs a(9, 4, 0.3, 7), b(9, 4, 0.3, 7), c(9, 4, 0.3, 8);
  const std::vector<double> xa = a.Generate(400), xb = b.Generate(400), xc = c.Generate(400);
  EXPECT_EQ(xa, xb);
  EXPECT_NE(xa, xc);
  for (std::size_t i = 0; i < xa.size(); i += 4) {
    for (int j = 1; j < 4; ++j) EXPECT_EQ(xa[i], xa[i + j]);
  }
  EXPECT_EQ(std::set<double>(xa.begin(), xa.end()), (std::set<double>{-0.3, 0.3}));
}

TEST(GaussianNoise, VarianceEqualsPowerInWatts) {
  GaussianNoise n(0.01, 1234);
  const std::vector<double> x = n.Generate(400000);
  const double mean = std::accumulate(x.begin(), x.end(), 0.0) / x.size();
  double var = 0.0;
  for (const double v : x) var += (v - mean) * (v - mean);
  var /= x.size();
  EXPECT_NEAR(mean, 0.0, 5 * 0.1 / std::sqrt(400000.0));
  EXPECT_NEAR(var / 0.01, 1.0, 0.01);
  EXPECT_DOUBLE_EQ(n.stddev(), 0.1);
}

TEST(GaussianNoise, TruncatedKeepsItsPowerAndItsBound) {
  for (const double clip : {1.5, 2.5, 3.0}) {
    GaussianNoise n(0.01, 77, clip);
    const std::vector<double> x = n.Generate(400000);
    double power = 0.0, peak = 0.0;
    for (const double v : x) {
      power += v * v;
      peak = std::max(peak, std::abs(v));
    }
    power /= x.size();
    EXPECT_NEAR(power / 0.01, 1.0, 0.01) << clip;
    EXPECT_LE(peak, n.bound()) << clip;
    EXPECT_GT(peak, 0.98 * n.bound()) << clip;  // the tails are still reached
    EXPECT_GT(n.stddev(), 0.1) << clip;         // raised to make up for the cut tails
  }
  EXPECT_THROW(GaussianNoise(0.01, 1, 0.5), std::invalid_argument);
}

TEST(GaussianNoise, SameSeedSameSequenceOtherSeedOtherSequence) {
  GaussianNoise a(1.0, 5), b(1.0, 5), c(1.0, 6);
  const std::vector<double> xa = a.Generate(1000);
  EXPECT_EQ(xa, b.Generate(1000));
  EXPECT_NE(xa, c.Generate(1000));
}

TEST(Steps, StepAndRandomStaircase) {
  const StepSignal s(1.0, 0.0, 2.0);
  EXPECT_EQ(s.Value(0.99), 0.0);
  EXPECT_EQ(s.Value(1.0), 2.0);
  const std::vector<double> r = RandomSteps(100, 10, 0.5, 3);
  EXPECT_EQ(r, RandomSteps(100, 10, 0.5, 3));
  for (std::size_t i = 0; i < r.size(); ++i) {
    EXPECT_LE(std::fabs(r[i]), 0.5);
    if (i % 10) {
      EXPECT_EQ(r[i], r[i - 1]);
    }
  }
}

TEST(TukeyEnvelope, FadesInAndOut) {
  EXPECT_EQ(TukeyEnvelope(0.0, 10.0, 1.0), 0.0);
  EXPECT_NEAR(TukeyEnvelope(0.5, 10.0, 1.0), 0.5, 1e-12);
  EXPECT_EQ(TukeyEnvelope(5.0, 10.0, 1.0), 1.0);
  EXPECT_NEAR(TukeyEnvelope(10.0, 10.0, 1.0), 0.0, 1e-12);
}

}  // namespace
}  // namespace odonata::signals
