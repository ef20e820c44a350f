#pragma once
// MAVLink 1 and 2 frames read from a stream of bytes, knowing no sockets: what a live link (a UDP
// port, a telemetry radio's serial port) and a telemetry log (.tlog) both carry.
//
// A MAVLink 1 frame: 0xFE, payload length, seq, sysid, compid, message id (1 byte), the payload,
// the checksum (2 bytes, little-endian). A MAVLink 2 frame: 0xFD, payload length, incompat flags,
// compat flags, seq, sysid, compid, message id (3 bytes, little-endian), the payload, the
// checksum, and 13 bytes of signature when incompat bit 0 is set (link id, a 6-byte timestamp and
// the 6-byte signature: the first 6 bytes of SHA-256 over the link's secret key and the frame up
// to the signature itself). The checksum is CRC-16/MCRF4XX over the frame after its start byte up
// to the checksum, then the message's CRC_EXTRA (mavlink_messages.hpp). MAVLink 2 cuts the
// payload's trailing zero bytes; the frame here holds it zero-extended to the message's length.
//
// What is dropped is counted, never thrown: a checksum that does not match, a message this table
// does not know (its checksum cannot be checked without its CRC_EXTRA), incompat flags other than
// signing (the spec says such frames must be dropped), a signature the given check refuses, a
// frame the end of the stream cut (Finish), and bytes that are no frame.
//
// Synchronisation: the stream is taken to start at a frame. Bytes that are no frame start, or a
// frame that fails its checksum, put the decoder out of step; it then resynchronises on the next
// frame it can verify, a known message whose checksum matches, looking at every byte after the
// failed one (a dropped byte on a serial link shifts everything after it, so the failed frame's
// length is not trusted). Until then, frames of unknown messages cannot be told from noise and are
// skipped with it, and a frame that fails its checksum is not counted again: bad_crc counts the
// places where the stream broke, bytes_skipped every byte lost there.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <utility>

#include "mavlink/mavlink_messages.hpp"

namespace odonata::mavlink {

inline constexpr std::uint8_t kStartV1 = 0xFE;
inline constexpr std::uint8_t kStartV2 = 0xFD;
inline constexpr std::size_t kHeaderSizeV1 = 6;   ///< start byte to message id
inline constexpr std::size_t kHeaderSizeV2 = 10;  ///< start byte to the 3-byte message id
inline constexpr std::size_t kChecksumSize = 2;
inline constexpr std::size_t kSignatureSize = 13;  ///< link id, timestamp (6), signature (6)
inline constexpr std::uint8_t kIncompatSigned = 0x01;
inline constexpr std::size_t kMaxPayloadSize = 255;
/// The longest frame: a signed MAVLink 2 frame with a 255-byte payload.
inline constexpr std::size_t kMaxFrameSize =
    kHeaderSizeV2 + kMaxPayloadSize + kChecksumSize + kSignatureSize;

/// One frame, as read.
struct Frame {
  std::uint8_t version = 2;  ///< 1 (0xFE) or 2 (0xFD)
  std::uint8_t incompat_flags = 0;
  std::uint8_t compat_flags = 0;
  std::uint8_t seq = 0;
  std::uint8_t sysid = 0;
  std::uint8_t compid = 0;
  std::uint32_t msgid = 0;
  /// The message's definition; nullptr for an id the table does not know.
  const MessageDef* message = nullptr;
  std::size_t wire_length = 0;  ///< payload bytes the frame carried
  std::size_t size = 0;         ///< bytes of the whole frame, start byte to signature
  /// The payload, zero-extended: bytes past wire_length are zero, so a message's fields read
  /// right at any truncation (and extensions a MAVLink 1 frame lacks read as zero).
  std::array<std::uint8_t, kMaxPayloadSize> payload{};

  bool is_signed() const { return (incompat_flags & kIncompatSigned) != 0; }
  /// The payload arrived shorter than the message (trailing zeros cut, or no extensions).
  bool truncated() const { return message != nullptr && wire_length < message->length; }
};

/// The value `field` refers to in `frame`'s payload.
/// @pre `field` was found (FindField) in frame.message.
inline double Field(const Frame& frame, const FieldRef& field) {
  return FieldValue(frame.payload.data(), field);
}

enum class FrameStatus : std::uint8_t {
  kOk,              ///< a known message whose checksum matches
  kBadCrc,          ///< a known message whose checksum does not match
  kUnknownMessage,  ///< a message id the table does not know: its checksum cannot be checked
  kIncompatible,    ///< MAVLink 2 incompat flags other than signing: to be dropped
  kNeedMore,        ///< the bytes end inside the frame
  kNoFrame,         ///< the first byte is no start byte (0xFD, 0xFE)
};

struct FrameRead {
  FrameStatus status = FrameStatus::kNoFrame;
  /// Bytes of the whole frame, as its header gives them; for kNeedMore, the bytes known to be
  /// needed so far (the header's when its length byte is missing); 0 for kNoFrame.
  std::size_t size = 0;
};

/// Reads the frame that starts at bytes[0]. Fills `frame`'s header (version, flags, seq, sysid,
/// compid, msgid, message, wire_length, size) for every status but kNoFrame and kNeedMore, and
/// its payload for kOk only.
FrameRead ReadFrame(std::string_view bytes, Frame& frame);

/// A sender's sequence numbers: each sender (sysid, compid) numbers its frames 0…255 and wraps,
/// so a number skipped is a frame sent and not received.
struct SenderStats {
  std::size_t frames = 0;  ///< frames followed
  std::size_t gaps = 0;    ///< places where numbers were skipped
  /// Numbers skipped: frames lost (a repeated frame counts 255, as pymavlink counts it).
  std::size_t lost = 0;
  std::uint8_t last_seq = 0;  ///< the number of the last frame followed
};

/// A sender's key in the maps below: sysid * 256 + compid.
inline std::uint16_t SenderKey(std::uint8_t sysid, std::uint8_t compid) {
  return static_cast<std::uint16_t>(sysid << 8 | compid);
}

/// Follows the sequence numbers of every sender.
class SequenceTracker {
 public:
  void Observe(std::uint8_t sysid, std::uint8_t compid, std::uint8_t seq);
  /// By SenderKey.
  const std::map<std::uint16_t, SenderStats>& senders() const { return senders_; }
  std::size_t lost() const { return lost_; }  ///< over all senders

 private:
  std::map<std::uint16_t, SenderStats> senders_;
  std::size_t lost_ = 0;
};

/// Distinct unknown message ids counted one by one (DecoderCounters, TlogFile).
inline constexpr std::size_t kMaxUnknownIds = 1024;

struct DecoderCounters {
  std::size_t frames_ok = 0;      ///< frames delivered
  std::size_t v1_frames = 0;      ///< of frames_ok, MAVLink 1
  std::size_t signed_frames = 0;  ///< of frames_ok, signed (see FrameDecoder::SignatureCheck)
  std::size_t truncated = 0;      ///< of frames_ok, with a payload zero-extended (Frame::truncated)
  std::size_t bad_crc = 0;        ///< places where a frame failed its checksum (see above)
  std::size_t bad_signature = 0;  ///< signed frames the signature check refused
  std::size_t unknown_message = 0;  ///< frames of ids the table does not know, by unknown_ids
  std::size_t incompatible = 0;     ///< frames with incompat flags other than signing
  std::size_t cut = 0;              ///< frames the end of the stream cut (Finish)
  /// Bytes passed over out of step: noise, and the bytes of frames that failed their checksum or
  /// were cut. Every byte fed is either in a frame counted above (delivered or dropped whole:
  /// unknown, incompatible, bad signature) or here.
  std::size_t bytes_skipped = 0;
  /// unknown_message by message id (the first kMaxUnknownIds distinct ids; later ones are
  /// counted in unknown_message only, so that a hostile stream cannot grow the map unbounded).
  std::map<std::uint32_t, std::size_t> unknown_ids;

  /// Frames dropped: everything counted but frames_ok and bytes_skipped.
  std::size_t dropped() const {
    return bad_crc + bad_signature + unknown_message + incompatible + cut;
  }
};

/// Decodes a byte stream incrementally: frames may be split across Feed calls at any byte.
class FrameDecoder {
 public:
  using FrameHandler = std::function<void(const Frame&)>;
  /// Tells whether a signed frame's signature is right, given the frame's bytes (start byte to
  /// the end of the signature): with the link's 32-byte secret key, the first 6 bytes of
  /// SHA-256(key + frame[0, size - 6)) equal frame[size - 6, size). Without a check, signatures
  /// are skipped (and signed frames counted); unsigned frames are the caller's to refuse.
  using SignatureCheck = std::function<bool(std::string_view frame_bytes)>;

  FrameDecoder() = default;
  explicit FrameDecoder(SignatureCheck check) : check_(std::move(check)) {}

  /// Decodes what `bytes` completes, calling `on_frame` for each frame delivered (in stream
  /// order; the frame is valid during the call only). Bytes of a frame not yet complete are kept
  /// for the next call (at most kMaxFrameSize - 1 of them).
  /// @pre on_frame does not call Feed or Finish on this decoder.
  void Feed(std::string_view bytes, const FrameHandler& on_frame);

  /// The end of the stream, or of a datagram (UDP carries whole frames): no byte will complete
  /// a kept frame. It is cut (counted when the decoder was in step), and the bytes after its
  /// start byte are read again out of step, delivering any frame they hold (a frame behind a
  /// corrupted length byte); the rest count as skipped. What is fed next is taken to start at a
  /// frame. @pre as Feed.
  void Finish(const FrameHandler& on_frame);

  const DecoderCounters& counters() const { return counters_; }
  /// Sequence numbers of frames delivered and of trusted frames of unknown messages, by sender.
  const SequenceTracker& sequences() const { return sequences_; }
  /// In step: the last frame read was verified or trusted (see above).
  bool synchronised() const { return synced_; }

 private:
  std::size_t Step(std::string_view at, const FrameHandler& on_frame);
  std::size_t SkipBytes(std::size_t n);
  std::size_t Deliver(std::string_view frame_bytes, const FrameHandler& on_frame);

  SignatureCheck check_;
  std::string pending_;  // bytes of a frame not yet complete
  Frame frame_;
  bool synced_ = true;
  DecoderCounters counters_;
  SequenceTracker sequences_;
};

}  // namespace odonata::mavlink
