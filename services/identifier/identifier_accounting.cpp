// The identifier's last line: every sample up to the newest heard, learned or counted.
#include <cstdio>

#include "identifier_node.hpp"

namespace odonata::identifier {

void IdentifierNode::PrintSampleAccounting() const {
  // newest + 1 = (resumed through + 1) + taken + lost + not learned: BusNode::Stop drained the
  // socket first, so nothing that reached the process is left out.
  if (config_.source != SampleSource::kSignals) return;
  const auto n = [](int64_t v) { return static_cast<long long>(v); };
  std::fprintf(stderr,
               "[%s] samples: newest seq %lld; resumed through seq %lld; %lld taken (%lld "
               "learned, the rest filled the lags), %lld lost on the way (gaps), %lld not "
               "learned\n",
               config_.instance.c_str(), n(stream_.newest_signals()), n(resumed_through_),
               n(samples_taken_), n(core_.samples_learned()), n(bus_.stats().gaps),
               n(not_learned_));
}

}  // namespace odonata::identifier
