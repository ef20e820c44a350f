#include "fit/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace odonata::fit {

bool StderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(ProgressStyle style)
    : style_(style), start_(Clock::now()), phase_start_(start_), quiet_(std::chrono::seconds(2)) {
  if (const char* env = std::getenv("ODONATA_PROGRESS_AFTER_S")) {
    char* end = nullptr;
    const double s = std::strtod(env, &end);
    if (end != env && s >= 0 && s < 1e6)
      quiet_ = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  }
}

std::string ProgressBar::TimeLeft(double elapsed_s, double fraction, double after_s) {
  if (!(fraction >= 0.02 && fraction < 1.0) || !(elapsed_s > 0.5)) return "";
  const double left = elapsed_s / fraction * (1.0 - fraction) +
                      (std::isfinite(after_s) ? std::max(0.0, after_s) : 0.0);
  char buf[32];
  if (left < 90)
    std::snprintf(buf, sizeof buf, "~%.0f s left", std::ceil(left));
  else
    std::snprintf(buf, sizeof buf, "~%.0f min left", std::ceil(left / 60));
  return buf;
}

void ProgressBar::Update(const std::string& label, double fraction, double after_s) {
  if (style_ == ProgressStyle::kOff) return;
  const auto now = Clock::now();
  fraction = std::clamp(fraction, 0.0, 1.0);
  if (fraction < last_fraction_) phase_start_ = now;  // a new phase: its own pace
  last_fraction_ = fraction;
  if (now - start_ < quiet_) return;  // a short fit stays quiet
  const double phase_s = std::chrono::duration<double>(now - phase_start_).count();
  const std::string left = TimeLeft(phase_s, fraction, after_s);
  const int percent = static_cast<int>(fraction * 100.0);
  if (style_ == ProgressStyle::kLines) {
    if (lined_ && now - last_line_ < std::chrono::seconds(10)) return;
    lined_ = true;
    last_line_ = now;
    std::fprintf(stderr, "odonata-fit: %s, %d%%%s%s\n", label.c_str(), percent,
                 left.empty() ? "" : ", ", left.c_str());
    return;
  }
  if (percent == last_percent_ && label == last_label_ && left.empty()) return;
  last_percent_ = percent;
  last_label_ = label;
  constexpr int kWidth = 30;
  const int filled = percent * kWidth / 100;
  std::fprintf(stderr, "\r%-28s [%s%s] %3d%%  %-14s", label.c_str(),
               std::string(filled, '#').c_str(), std::string(kWidth - filled, '.').c_str(), percent,
               left.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::Finish() {
  if (style_ == ProgressStyle::kBar && drawn_) {
    std::fprintf(stderr, "\r%*s\r", 86, "");
    std::fflush(stderr);
    drawn_ = false;
  }
}

}  // namespace odonata::fit
