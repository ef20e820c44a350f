#pragma once
// A one-line progress bar on stderr, drawn only when stderr is a terminal so logs stay clean.

#include <string>

namespace odonata::fit {

class ProgressBar {
 public:
  /// @param enabled false makes every call a no-op.
  explicit ProgressBar(bool enabled) : enabled_(enabled) {}
  ~ProgressBar() { Finish(); }
  /// Redraws "label [#####.....] 42%" when the percentage changes.
  void Update(const std::string& label, double fraction);
  void Finish();

 private:
  bool enabled_;
  bool drawn_ = false;
  int last_percent_ = -1;
  std::string last_label_;
};

/// True when fd 2 is a terminal.
bool StderrIsTerminal();

}  // namespace odonata::fit
