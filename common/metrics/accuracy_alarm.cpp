#include "metrics/accuracy_alarm.hpp"

#include <cmath>

namespace odonata::metrics {

AccuracyAlarm::AccuracyAlarm(const AccuracyAlarmOptions& options)
    : options_(options),
      window_(options.window, options.span > 0 ? options.span : 10 * options.window) {
  if (!(options_.reference_samples > 0.0)) {
    options_.reference_samples = 3.0 * static_cast<double>(options_.window);
  }
}

std::optional<AccuracyEvent> AccuracyAlarm::Push(long sample, double measured, double predicted) {
  if (!std::isfinite(measured) || !std::isfinite(predicted)) return std::nullopt;
  window_.Add(measured, predicted);
  if (!window_.ready()) return std::nullopt;
  window_fit_ = window_.fit_percent();
  if (!std::isfinite(window_fit_)) return std::nullopt;  // a constant window says nothing
  if (!alarmed_) {
    // The reference needs a window's worth of settled history before it means anything.
    if (!have_reference_) {
      reference_ = window_fit_;
      have_reference_ = true;
    } else {
      const double a = 1.0 / options_.reference_samples;
      reference_ += a * (window_fit_ - reference_);
    }
    ++settled_;
    if (settled_ > static_cast<long>(options_.window) &&
        window_fit_ < reference_ - options_.drop_points) {
      alarmed_ = true;
      return AccuracyEvent{AccuracyEvent::Kind::kAlarm, sample, window_fit_, reference_};
    }
    return std::nullopt;
  }
  if (window_fit_ >= reference_ - options_.recover_points) {
    alarmed_ = false;
    settled_ = 0;
    return AccuracyEvent{AccuracyEvent::Kind::kRecovered, sample, window_fit_, reference_};
  }
  return std::nullopt;
}

}  // namespace odonata::metrics
