#pragma once
// prediction_t → the scoreboard's Prediction: one home for the conversion the monitor and the
// log export's scoring both need, so a field added to the message is scored by both.

#include "monitoring/prediction_scoreboard.hpp"
#include "odonata/prediction_t.hpp"

namespace odonata::monitoring {

/// The arrays as sent; PredictionScoreboard::Add checks that they agree.
inline Prediction PredictionFromMessage(const odonata::prediction_t& m) {
  Prediction p;
  p.sample = m.sample;
  p.names = m.names;
  p.measured = m.measured;
  p.predicted = m.predicted;
  p.free_run = m.free_run;
  p.rules = m.rules;
  p.arx_predicted = m.arx_predicted;
  p.arx_free_run = m.arx_free_run;
  p.linear_share = m.linear_share;
  p.horizon = m.horizon;
  p.ahead = m.ahead;
  p.arx_ahead = m.arx_ahead;
  p.interval_level = m.interval_level;
  p.half_width = m.half_width;
  p.ahead_half_width = m.ahead_half_width;
  p.free_run_half_width = m.free_run_half_width;
  p.seen_enough.assign(m.seen_enough.begin(), m.seen_enough.end());
  return p;
}

}  // namespace odonata::monitoring
