#pragma once
// Progress of a long fit on stderr, with the time left: a redrawn bar on a terminal, or a line
// every 10 s into a log (docs/identifier.md §9). A fit shorter than 2 s shows nothing (the
// environment variable ODONATA_PROGRESS_AFTER_S sets another quiet time).

#include <chrono>
#include <string>

namespace odonata::fit {

enum class ProgressStyle {
  kOff,    ///< nothing (--json into a pipe)
  kBar,    ///< "label [#####.....] 42%  ~12 s left", redrawn in place (a terminal)
  kLines,  ///< the same as a line of its own every 10 s (a log file)
};

class ProgressBar {
 public:
  explicit ProgressBar(ProgressStyle style);
  /// Off unless `enabled` (a terminal bar).
  explicit ProgressBar(bool enabled)
      : ProgressBar(enabled ? ProgressStyle::kBar : ProgressStyle::kOff) {}
  ~ProgressBar() { Finish(); }
  /// `fraction` of the current phase is done; a fraction below the last one starts a new phase
  /// (the selection, the epochs, the simulation stages), whose time left is estimated from its
  /// own pace, plus `after_s`: what the phases after it are expected to take.
  void Update(const std::string& label, double fraction, double after_s = 0.0);
  void Finish();
  /// "~12 s left", "~3 min left", or "" before the pace is known.
  static std::string TimeLeft(double elapsed_s, double fraction, double after_s = 0.0);

 private:
  using Clock = std::chrono::steady_clock;
  ProgressStyle style_;
  Clock::time_point start_, phase_start_;
  Clock::duration quiet_;
  bool lined_ = false;
  Clock::time_point last_line_;
  double last_fraction_ = -1.0;
  bool drawn_ = false;
  int last_percent_ = -1;
  std::string last_label_;
};

/// True when fd 2 is a terminal.
bool StderrIsTerminal();

}  // namespace odonata::fit
