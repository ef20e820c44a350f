// Whether the model has seen enough (SettlingWatch, docs/identifier.md §7.7), said where a pilot
// looks: the heartbeat's detail (the monitor prints it), GET's answer, and a line on stderr each
// time an output's state changes, so a run can be read after the flight.
#include <cstdio>

#include "identifier_node.hpp"

namespace odonata::identifier {

void IdentifierNode::ReportSettling(SettlingJudgement when) {
  const int64_t learned = core_.samples_learned();
  if (when == SettlingJudgement::kWhenDue && learned >= settling_judged_at_ &&
      learned - settling_judged_at_ < kSettlingEvery)
    return;
  settling_judged_at_ = learned;
  const auto judged = core_.Settling();
  const auto& names = core_.model().spec().outputs;
  settling_said_.resize(judged.size(), -1);
  settling_.assign(judged.size(), 0);
  std::string detail;
  for (std::size_t o = 0; o < judged.size(); ++o) {
    const std::string line = names[o] + ": " + judged[o].sentence;
    detail += (o ? "\n" : "") + line;
    const int state = static_cast<int>(judged[o].state);
    settling_[o] = state;
    if (state != settling_said_[o]) {
      std::fprintf(stderr, "%s: %s (%lld samples learned)\n", config_.instance.c_str(),
                   line.c_str(), static_cast<long long>(learned));
      settling_said_[o] = state;
    }
  }
  bus_.stats().detail = detail;
}

}  // namespace odonata::identifier
