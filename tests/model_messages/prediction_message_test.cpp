// The identifier's report → prediction_t: the intervals travel with their level, an unknown width
// (+∞: too few residuals yet) as −1, since receivers drop messages carrying non-finite values.
#include "model_messages/prediction_message.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace odonata::model_messages {
namespace {

TEST(PredictionMessage, CarriesTheIntervalsAndSaysUnknownWidthsAsMinusOne) {
  sysid::SampleReport r;
  r.index = 7;
  r.measured = Eigen::Vector2d(1.0, 2.0);
  r.predicted = r.free_run = r.next = r.max_entropy = r.arx_predicted = r.arx_free_run = r.measured;
  r.rules = Eigen::Vector2i(3, 4);
  r.ahead = r.arx_ahead = r.measured;
  r.horizon = 5;
  r.interval_level = 0.9;
  r.half_width = Eigen::Vector2d(0.25, std::numeric_limits<double>::infinity());
  r.ahead_half_width = Eigen::Vector2d(std::numeric_limits<double>::infinity(), 0.5);
  r.free_run_half_width = Eigen::Vector2d(1.5, std::numeric_limits<double>::infinity());
  r.seen_enough = {sysid::SettlingState::kSettled, sysid::SettlingState::kShortOfExcitation};
  const odonata::prediction_t p = ToPredictionMessage(r, {"roll", "pitch"}, 1, 2);
  EXPECT_DOUBLE_EQ(p.interval_level, 0.9);
  EXPECT_EQ(p.num_intervals, 2);
  EXPECT_EQ(p.half_width, (std::vector<double>{0.25, -1.0}));
  EXPECT_EQ(p.ahead_half_width, (std::vector<double>{-1.0, 0.5}));
  EXPECT_EQ(p.num_free_run_intervals, 2);
  EXPECT_EQ(p.free_run_half_width, (std::vector<double>{1.5, -1.0}));
  EXPECT_EQ(p.num_seen_enough, 2);
  EXPECT_EQ(p.seen_enough, (std::vector<int8_t>{odonata::prediction_t::SEEN_SETTLED,
                                                odonata::prediction_t::SEEN_SHORT}));
  // Without a horizon, no K-step widths.
  r.ahead.resize(0);
  r.ahead_half_width.resize(0);
  EXPECT_TRUE(ToPredictionMessage(r, {"roll", "pitch"}, 1, 2).ahead_half_width.empty());
  // A report without the watch's states (sized otherwise) carries none rather than a wrong one.
  r.seen_enough.clear();
  EXPECT_EQ(ToPredictionMessage(r, {"roll", "pitch"}, 1, 2).num_seen_enough, 0);
}

}  // namespace
}  // namespace odonata::model_messages
