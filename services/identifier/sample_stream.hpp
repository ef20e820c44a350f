#pragma once
// The identifier's samples from the vehicle's messages, without transport: pairs commands,
// states and beat states (messages/paired_sample.hpp), reads the model's signals from them and,
// with decimation, averages each block into one sample at the lower rate. The shell feeds it
// what the bus delivers and learns from what comes out.

#include <cstdint>
#include <string>
#include <vector>

#include "io/row_decimator.hpp"
#include "messages/paired_sample.hpp"
#include "odonata/signals_t.hpp"
#include "sequence/sample_sequence.hpp"
#include "sysid/model/regressor_spec.hpp"
#include "sysid/online/online_identifier.hpp"

namespace odonata::identifier {

class SampleStream {
 public:
  struct Event {
    enum class Kind {
      kSample,   ///< `sample` is ready to learn from
      kGap,      ///< `lost` samples are lost: `what` (report kind) and `message` say why
      kRestart,  ///< the plant restarted its run: restart the model's history
    };
    Kind kind = Kind::kSample;
    sysid::Sample sample;
    int64_t lost = 0;
    std::string what, message;
  };

  /// @param decimate one sample per block of this many (io::RowDecimator). @pre ≥ 1.
  SampleStream(sysid::RegressorSpec spec, int decimate);

  /// Each throws std::invalid_argument, and changes nothing, for a message with NaN or Inf, bad
  /// counts or a seq the pairing rules reject.
  std::vector<Event> OnCommand(const odonata::wing_command_t& msg);
  std::vector<Event> OnState(const odonata::plant_state_t& msg);
  std::vector<Event> OnBeat(const odonata::beat_state_t& msg);
  /// Any vehicle's sample k by name (source "signals"), in the order sequence/sample_sequence.hpp
  /// rules (gaps, restarts, stale seqs, leaps). Throws for a message it drops, or without one of
  /// the model's signals or with one that is not finite.
  std::vector<Event> OnSignals(const odonata::signals_t& msg);

  /// Samples are formed from now on; before, messages are paired (so gaps and restarts are
  /// still seen) but make no sample, as when the identifier waits for a snapshot to resume from.
  void Start() { started_ = true; }

  /// Whether the model's signals need beat states at all (else nobody need subscribe to them).
  bool needs_beat_states() const { return pairer_.needs().beat || pairer_.needs().next_beat; }
  /// What a lockstep receipt acknowledges (pipeline::SamplePairer::newest_held_state()).
  int64_t newest_held_state() const { return pairer_.newest_held_state(); }
  /// The newest signals_t sample taken in order (−1 before any): what a replay's lockstep receipt
  /// acknowledges, and the seq whose repeat is a resend.
  int64_t newest_signals() const { return signals_sequence_.newest(); }

 private:
  std::vector<Event> Form(const std::vector<messages::PairedMessages>& paired);
  // Sample k from its messages, or nothing while a decimated block is incomplete.
  bool FormSample(const messages::PairedMessages& paired, sysid::Sample* sample);
  // With decimation, folds sample k into its block: true when the block's sample is ready.
  bool Decimate(sysid::Sample* sample);

  sysid::RegressorSpec spec_;
  messages::MessagePairer pairer_;
  io::RowDecimator decimator_;
  // A run begins (the first state or signals of the stream, or a confirmed restart): the
  // decimator starts a fresh block, and the kRestart event restarts the model's history.
  Event RunBegins();

  bool started_ = false;
  bool state_seen_ = false;    // a state has been taken: a seq 0 after it is the pairer's restart
  bool signals_seen_ = false;  // likewise for signals
  pipeline::SampleSequence signals_sequence_;
};

}  // namespace odonata::identifier
