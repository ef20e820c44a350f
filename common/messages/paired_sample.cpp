#include "messages/paired_sample.hpp"

#include <stdexcept>

#include "messages/beat_state_message.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/wing_command_message.hpp"

namespace odonata::messages {

pipeline::PairingNeeds PairingNeedsOf(const std::vector<std::string>& signals) {
  pipeline::PairingNeeds needs;
  for (const auto& name : signals) {
    const auto offset = BeatStateOffset(name);
    if (offset) (*offset == 0 ? needs.beat : needs.next_beat) = true;
  }
  return needs;
}

std::optional<double> PairedSignal(const PairedMessages& e, const std::string& name) {
  if (name == "t_s") return e.state.t_s;
  if (const auto offset = BeatStateOffset(name)) {
    const auto& beat = *offset == 0 ? e.beat : e.next_beat;
    if (!beat) throw std::invalid_argument("no beat state paired for '" + name + "'");
    return BeatStateField(*beat, name);
  }
  if (auto v = CommandField(e.command, name)) return v;
  return StateField(e.state, name);
}

}  // namespace odonata::messages
