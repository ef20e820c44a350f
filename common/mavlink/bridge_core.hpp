#pragma once
// The core of odonata-mavlink: MAVLink bytes in, the fields a user names out, on one uniform grid
// by the same rules as every other source (timeseries/uniform_grid.hpp). It knows no sockets and
// no LCM: the service feeds it what a UDP port or a serial port delivers, with the time it
// arrived, and publishes what TakeSamples returns.
//
// Fields: "MESSAGE.field" ("ATTITUDE.pitchspeed"), an array element "MESSAGE.field[i]"
// ("ACTUATOR_OUTPUT_STATUS.actuator[1]", from 0 as pymavlink indexes), and "MESSAGE@sysid:compid.
// field" ("ATTITUDE@1:1.pitch") when several vehicles or components share the link. A plain name
// locks onto the first sender heard sending its message (a live link cannot know which sender
// will send most, as tlog_signals' plain names mean); frames of a named message from any sender no
// field takes are counted in other_sender, never read.
//
// Time base: each frame's ARRIVAL time, in seconds, as the caller gives it (a live link has no
// other clock common to every message: the vehicle's time_boot_ms is a field like any other). A
// .tlog replayed gives its record timestamps relative to its first record, as tlog_signals does,
// so that the bridge and odonata-fit put the same sample at the same time. Arrival times should
// not go backwards; a field's sample timed earlier than its previous one is dropped and counted
// in out_of_order, so each field's times are non-decreasing (the same rule as tlog_signals).
// A non-finite value is no sample (as timeseries::Resample reads it).
//
// The grid (the rules of timeseries::Resample, with its arithmetic, so that the values are the
// same to the last bit):
//  - t0 = the latest of the named fields' first sample times: the first time every field has a
//    sample. Sample k lies at t_k = t0 + k / rate (each from its index: no rounding accumulates).
//  - Rate: BridgeOptions::rate_hz, or with 0 the slowest median rate (timeseries::MedianRateHz)
//    of the interpolated fields (of all fields when none is) over each field's first
//    kRateWindowS seconds of samples, chosen once every field has a sample that far after its
//    first; said by rate_note(). No grid sample is made before the rate is known.
//  - A grid sample is complete, and made, once every field has a sample strictly after
//    t_k + eps (eps = 1e-9 period): then no later sample can change it. With period = 1 / rate
//    and reach = (max_gap + 1) period (1 + 1e-9), for an interpolated field with samples
//    (t_j, v_j) at or before t_k + eps and (t_j+1, v_j+1) after it:
//      |t_j - t_k| <= eps            -> v_j
//      t_j+1 - t_j > reach           -> NaN (a gap)
//      otherwise                     -> v_j + (v_j+1 - v_j) (t_k - t_j) / (t_j+1 - t_j)
//    A held field (uint8_t: modes, flags, ids, counts, as tlog_signals reads them) takes v_j.
//    A sample with a NaN is a gap: counted in gap_samples, for the caller not to send.
//  - A field silent for a while holds the grid back: its rows are made when it is heard again
//    (NaN where its gap is longer than the rule bridges). Silent() names it meanwhile.
//
// Memory: per field, the samples from the one the next grid time needs onwards (the earlier ones
// are dropped as each grid sample is made, and before the grid starts those before the latest
// first sample); at most kMaxBufferedSamples per field while another field holds the grid back,
// the oldest dropped beyond (counted in overflow_dropped; cells needing them read NaN). Grid
// samples made wait in the core until TakeSamples.
//
// Dropped frames are the decoder's to count (frame_decoder.hpp: bad checksum, unknown message,
// incompatible flags, bad signature, bytes out of step), sequence gaps per sender too; Summary
// shows them with the bridge's own counts.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "mavlink/frame_decoder.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "timeseries/uniform_grid.hpp"

namespace odonata::mavlink {

/// Seconds of each field's first samples its median rate is taken over when the rate is chosen.
inline constexpr double kRateWindowS = 2.0;
/// Samples kept per field at most while the grid waits for another field.
inline constexpr std::size_t kMaxBufferedSamples = std::size_t{1} << 16;

/// One named field, parsed.
struct FieldSelector {
  std::string name;                           ///< as the user wrote it: "ATTITUDE@1:1.pitch"
  std::string message;                        ///< "ATTITUDE"
  std::string field;                          ///< "pitch", "actuator[1]"
  std::optional<std::uint8_t> sysid, compid;  ///< both or neither: the sender asked for
};

/// Parses "MESSAGE.field", "MESSAGE.field[i]" or "MESSAGE@sysid:compid.field".
/// @throws std::invalid_argument saying what is wrong: no '.', a sender that is not two numbers
///   0..255, a message the table does not know or a field it does not have (each with the nearest
///   known name), an array without an index, a text (char) field.
FieldSelector ParseFieldSelector(const std::string& text);

/// What a link with a key (BridgeOptions::signature_check) does with an unsigned frame.
enum class UnsignedFrames : std::uint8_t {
  kAccept,  ///< take it (no key, or a key and senders that do not sign yet)
  kRefuse,  ///< drop it, counted in unsigned_refused (a key given: only signed frames count)
};

struct BridgeOptions {
  std::vector<std::string> fields;  ///< as ParseFieldSelector takes them; at least one
  /// The grid's rate, Hz; 0: once every field has kRateWindowS seconds of samples, the slowest
  /// interpolated field's median rate over them (said by rate_note()).
  double rate_hz = 0.0;
  int max_gap = 3;         ///< the gap rule's (timeseries::GridOptions::max_gap)
  double silence_s = 3.0;  ///< a named field not heard for this long is reported by Silent()
  /// The link's signature check (link_signature.hpp's SignatureCheckFor); empty: signatures are
  /// not checked. A signed frame it refuses is dropped and counted (bad_signature).
  FrameDecoder::SignatureCheck signature_check;
  UnsignedFrames unsigned_frames = UnsignedFrames::kAccept;
  /// Called with every frame delivered and not refused, before its fields are read (the
  /// service's --request-rate learns there that the vehicle is heard and answers).
  std::function<void(const Frame&)> on_frame;
};

/// One grid sample.
struct GridSample {
  std::int64_t k = 0;          ///< its index: t_s = t0 + k / rate
  double t_s = 0.0;            ///< arrival-time base (see above)
  std::vector<double> values;  ///< one per named field, in BridgeOptions::fields order
  bool gap() const;            ///< a value is NaN: a gap, not to be sent
};

class BridgeCore {
 public:
  /// @throws std::invalid_argument for no fields, a field ParseFieldSelector refuses, the same
  ///   field named twice, a negative or non-finite rate, a negative max_gap, a silence_s <= 0.
  explicit BridgeCore(BridgeOptions options);

  /// Decodes `bytes` (frames may be split across calls at any byte), keeps the named fields'
  /// samples at `arrival_s` and makes the grid samples they complete.
  void Feed(std::string_view bytes, double arrival_s);
  /// The end of a datagram (UDP carries whole frames): a frame left incomplete is cut and counted
  /// (FrameDecoder::Finish); what is fed next starts a frame.
  void EndOfDatagram(double arrival_s);

  /// The grid samples made since the last call, in order of k (each once).
  std::vector<GridSample> TakeSamples();

  const DecoderCounters& counters() const { return decoder_.counters(); }
  const SequenceTracker& sequences() const { return decoder_.sequences(); }
  /// The named fields (as given) not heard within silence_s before `now_s`: never heard since
  /// the first byte fed, or last heard more than silence_s ago. Empty before anything was fed.
  std::vector<std::string> Silent(double now_s) const;

  /// The named fields, as given (BridgeOptions::fields): the names published.
  const std::vector<std::string>& field_names() const { return options_.fields; }
  double silence_s() const { return options_.silence_s; }
  double rate_hz() const { return rate_hz_; }  ///< 0 until chosen
  /// How the rate came: given, chosen (which field, its median rate), or still awaited.
  std::string rate_note() const;
  /// t0: the first grid time; NaN until every field has a sample.
  double t0_s() const { return t0_s_; }
  std::size_t grid_samples() const { return grid_samples_; }  ///< made so far
  std::size_t gap_samples() const { return gap_samples_; }    ///< of those, with a NaN
  /// Frames the bridge itself dropped: another sender's frames of a named message, unsigned
  /// frames refused, and samples out of order or beyond the buffer (decoder drops apart).
  std::size_t bridge_dropped() const;
  std::size_t unsigned_refused() const { return unsigned_refused_; }
  /// Per named message, the senders heard sending it that no field takes ("ATTITUDE" → {"2:1"}):
  /// a second vehicle on the link, which a plain name does not follow.
  const std::map<std::string, std::set<std::string>>& other_senders() const {
    return other_senders_;
  }

  /// Counts, the grid, and per field its samples and when last heard, as JSON.
  nlohmann::json Summary() const;

 private:
  struct Sample {
    double t_s = 0.0;
    double value = 0.0;
  };
  struct NamedField {
    FieldSelector selector;
    const MessageDef* message = nullptr;
    FieldRef ref;
    timeseries::Interpolation interpolation = timeseries::Interpolation::kLinear;
    std::optional<std::uint16_t> sender;  ///< SenderKey, given or locked onto
    std::deque<Sample> samples;           ///< kept (see Memory above)
    std::size_t frames = 0;               ///< frames of its message from its sender
    double last_heard_s = 0.0;            ///< arrival of the last of them (when frames > 0)
    std::size_t accepted = 0;             ///< samples kept: finite, in time order
    std::size_t out_of_order = 0;
    std::size_t overflow_dropped = 0;
    double first_s = 0.0;                 ///< its first sample's time (when accepted > 0)
    double last_s = 0.0;                  ///< its last sample's time (when accepted > 0)
    std::vector<double> rate_window_t_s;  ///< times within kRateWindowS of first_s (rate 0)
  };

  void OnFrame(const Frame& frame, double arrival_s);
  void ChooseRate();
  void SetRate(double rate_hz);
  void Advance();
  void Prune(double t_s);
  double ValueAt(const NamedField& f, double t_s) const;

  BridgeOptions options_;
  std::vector<NamedField> fields_;
  FrameDecoder decoder_;
  double rate_hz_ = 0.0;
  bool rate_refused_ = false;  ///< rate 0 and no field had a rate in its first kRateWindowS
  double period_s_ = 0.0;      ///< 1 / rate_hz_, once known
  double eps_s_ = 0.0;         ///< 1e-9 period: a sample this close to a grid time is on it
  double reach_s_ = 0.0;       ///< (max_gap + 1) period (1 + 1e-9): the longest span bridged
  std::string rate_note_;
  double t0_s_;
  std::int64_t next_k_ = 0;
  std::optional<double> first_arrival_s_;
  std::vector<GridSample> ready_;
  std::size_t grid_samples_ = 0;
  std::size_t gap_samples_ = 0;
  std::size_t other_sender_ = 0;  ///< frames of a named message no field took (another sender)
  std::size_t unsigned_refused_ = 0;
  std::map<std::string, std::set<std::string>> other_senders_;
};

}  // namespace odonata::mavlink
