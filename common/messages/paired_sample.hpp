#pragma once
// Sample k as the bus delivers it: the pipeline's SamplePairer over the vehicle's messages, and
// each named signal read from the message that carries it. The identifier learns from these
// samples and odonata-logger export writes them as rows, so both pair and name alike.

#include <optional>
#include <string>
#include <vector>

#include "odonata/beat_state_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/wing_command_t.hpp"
#include "pipeline/sample_pairer.hpp"

namespace odonata::messages {

using MessagePairer =
    pipeline::SamplePairer<odonata::plant_state_t, odonata::wing_command_t, odonata::beat_state_t>;
using PairedMessages = MessagePairer::Event;

/// The beat states that samples of these signals need.
pipeline::PairingNeeds PairingNeedsOf(const std::vector<std::string>& signals);

/// Signal `name` of sample k: a beat average from beat state k, an applied channel from beat
/// state k + 1, a command or excitation from the command, else an output from state k ("t_s" is
/// state k's time); nullopt when no message of the sample has it.
/// @throws std::invalid_argument when `name` needs a beat state the sample was paired without.
std::optional<double> PairedSignal(const PairedMessages& sample, const std::string& name);

}  // namespace odonata::messages
