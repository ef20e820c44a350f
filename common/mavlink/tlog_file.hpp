#pragma once
// A MAVLink telemetry log (.tlog, as ground stations record a link: Mission Planner,
// QGroundControl, MAVProxy) read into memory: each record is an 8-byte big-endian timestamp
// (microseconds since the Unix epoch, when the ground station received the frame) followed by one
// raw MAVLink 1 or 2 frame (frame_decoder.hpp). The frames of the messages the table knows
// (mavlink_messages.hpp) are kept per message and sender, their payloads zero-extended; the
// others are counted by message id.
//
// Damage does not stop the reading: a record whose timestamp is no date between 2000 and 2100 or
// whose frame does not start with 0xFD or 0xFE, and a frame that fails its checksum, are skipped
// to the next place where a record can be verified: a plausible timestamp and a start byte, then a
// frame of a known message whose checksum matches, or a frame of an unknown message followed by
// another plausible record (or the end of the file). The bytes skipped are counted, and a last
// record cut by the end of the file (the recording stopped mid-write) is reported. The first
// damage is in `problem`, with its byte offset. Only bytes that are no telemetry log at all (or a
// file that cannot be read) throw.
//
// Memory: the payloads of the known messages, zero-extended, and 8 bytes of time per frame: about
// the file's size for real logs (payloads are cut of zeros only), at worst 7.4 times it (records
// of 20 bytes, each kept as a 140-byte ACTUATOR_OUTPUT_STATUS); files over kMaxTlogBytes are
// refused.

#include <cstddef>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "mavlink/frame_decoder.hpp"
#include "mavlink/mavlink_messages.hpp"

namespace odonata::mavlink {

/// Raised for bytes that are no telemetry log at all (or a file that cannot be read): damage
/// inside a log is reported in TlogFile::problem instead.
class TlogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The largest file Read and Parse take (2 GiB).
inline constexpr std::size_t kMaxTlogBytes = std::size_t{1} << 31;
inline constexpr std::size_t kTlogTimestampSize = 8;
/// Timestamps a record may carry: from 2000-01-01 to before 2100-01-01, µs since the Unix epoch.
inline constexpr std::uint64_t kEarliestTlogTimeUs = 946'684'800'000'000;
inline constexpr std::uint64_t kLatestTlogTimeUs = 4'102'444'800'000'000;

/// The frames of one message from one sender (sysid, compid), in file order.
struct MessageSeries {
  const MessageDef* message = nullptr;
  std::uint8_t sysid = 0;
  std::uint8_t compid = 0;
  std::vector<std::uint64_t> times_us;  ///< each frame's record timestamp
  /// Frame i's payload, zero-extended to the message's length (bytes of extensions the table
  /// does not know are dropped), at [i * message->length, (i + 1) * message->length).
  std::vector<std::uint8_t> payloads;
  std::size_t truncated = 0;  ///< frames whose payload arrived shorter than the message

  std::size_t size() const { return times_us.size(); }
  const std::uint8_t* Payload(std::size_t i) const { return payloads.data() + i * message->length; }
  /// The value `field` refers to in frame `i`. @pre field was found in *message; i < size().
  double Value(std::size_t i, const FieldRef& field) const { return FieldValue(Payload(i), field); }
  /// "1:1": sysid:compid.
  std::string sender() const { return std::to_string(sysid) + ":" + std::to_string(compid); }
};

struct TlogFile {
  std::string source;  ///< the path or name it was read from
  std::size_t file_size = 0;
  /// The timestamp of the first record read: the zero of the signals' times (tlog_signals.hpp).
  std::uint64_t first_time_us = 0;
  std::uint64_t last_time_us = 0;  ///< of the last record read

  /// Per message and sender, sorted by message name, then sysid, then compid.
  std::vector<MessageSeries> series;

  std::size_t records = 0;  ///< records read: a timestamp and a whole frame, known or not
  std::map<std::uint32_t, std::size_t> frame_counts;  ///< records read by message id
  /// Of those, ids the table does not know (their checksum cannot be checked): counted, not
  /// kept. The first kMaxUnknownIds distinct ids are counted one by one.
  std::map<std::uint32_t, std::size_t> unknown_counts;
  std::size_t unknown_frames = 0;
  std::size_t v1_frames = 0;
  std::size_t signed_frames = 0;  ///< signatures are not checked: a log holds no key
  /// Frames with MAVLink 2 incompat flags other than signing, which the spec says to drop.
  std::size_t incompatible = 0;
  std::size_t bad_crc = 0;  ///< frames of known messages whose checksum does not match
  /// Sequence numbers by sender (SenderKey): frames the ground station did not receive.
  SequenceTracker sequences;

  /// Bytes read as no record: between records (resynchronised), frames failing their checksum,
  /// and a cut last record.
  std::size_t bytes_skipped = 0;
  std::size_t damage_count = 0;  ///< places where bytes were skipped
  /// What was odd but readable: incompatible frames, times going backwards.
  std::vector<std::string> notes;

  /// Empty when every byte was read as a record; else the first damage, e.g. "the last record,
  /// at byte 1510240, is cut: its frame needs 40 bytes, only 15 are left".
  std::string problem;
  std::uint64_t problem_offset = 0;  ///< byte offset of that damage
  bool complete() const { return problem.empty(); }

  /// The frames of `message` from sysid:compid, or nullptr.
  const MessageSeries* Find(std::string_view message, std::uint8_t sysid,
                            std::uint8_t compid) const;
  /// The frames of `message` from the sender that sent most of them (the lowest sysid, then
  /// compid, on a tie), or nullptr when there are none.
  const MessageSeries* FindMain(std::string_view message) const;
  /// Frames of the known message `message` read, from every sender (0 for an unknown name).
  std::size_t FrameCount(std::string_view message) const;
};

/// The record timestamp whose kTlogTimestampSize big-endian bytes start at `p`, in µs.
inline std::uint64_t TlogStampAt(const char* p) {
  std::uint64_t t = 0;
  for (std::size_t i = 0; i < kTlogTimestampSize; ++i)
    t = (t << 8) | static_cast<std::uint8_t>(p[i]);
  return t;
}

/// Seconds from `zero_us` to `t_us` (negative before it): the exact difference of microseconds,
/// divided once. Every reading of a .tlog's times uses it (tlog_signals, odonata-mavlink
/// --udp-stamped), so that they agree to the last bit.
inline double TlogSeconds(std::uint64_t t_us, std::uint64_t zero_us) {
  return t_us >= zero_us ? static_cast<double>(t_us - zero_us) / 1e6
                         : -static_cast<double>(zero_us - t_us) / 1e6;
}

/// Whether `head` (the first bytes of a file, 9 or more) starts a telemetry log: a big-endian
/// timestamp between 2000 and 2100, then a MAVLink start byte (0xFD or 0xFE) at byte 8. Content,
/// not the file's name.
bool LooksLikeTlog(std::string_view head);

/// Parses telemetry log bytes; `source` names them in messages. Damage is reported in `problem`.
/// @throws TlogError for empty bytes, bytes that do not start like a telemetry log, or more
///   than kMaxTlogBytes.
TlogFile Parse(std::string_view bytes, const std::string& source);

/// Reads the telemetry log at `path`.
/// @throws TlogError if it cannot be opened or read, or as Parse.
TlogFile Read(const std::string& path);

}  // namespace odonata::mavlink
