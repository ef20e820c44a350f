#include "mavlink/frame_decoder.hpp"

#include <cstring>

#include "mavlink/mavlink_crc.hpp"

namespace odonata::mavlink {
namespace {

bool IsStartByte(char c) {
  const auto b = static_cast<std::uint8_t>(c);
  return b == kStartV1 || b == kStartV2;
}

}  // namespace

FrameRead ReadFrame(std::string_view bytes, Frame& frame) {
  if (bytes.empty()) return FrameRead{FrameStatus::kNeedMore, 1};
  const auto* b = reinterpret_cast<const std::uint8_t*>(bytes.data());
  const bool v2 = b[0] == kStartV2;
  if (!v2 && b[0] != kStartV1) return FrameRead{FrameStatus::kNoFrame, 0};
  const std::size_t header = v2 ? kHeaderSizeV2 : kHeaderSizeV1;
  // The length byte, and in MAVLink 2 the incompat flags, say how long the frame is.
  if (bytes.size() < (v2 ? 3u : 2u)) return FrameRead{FrameStatus::kNeedMore, header};
  const std::size_t length = b[1];
  const std::uint8_t incompat = v2 ? b[2] : 0;
  const std::size_t size = header + length + kChecksumSize +
                           ((incompat & kIncompatSigned) != 0 ? kSignatureSize : std::size_t{0});
  if (bytes.size() < size) return FrameRead{FrameStatus::kNeedMore, size};

  frame.version = v2 ? 2 : 1;
  if (v2) {
    frame.incompat_flags = b[2];
    frame.compat_flags = b[3];
    frame.seq = b[4];
    frame.sysid = b[5];
    frame.compid = b[6];
    frame.msgid = static_cast<std::uint32_t>(b[7]) | static_cast<std::uint32_t>(b[8]) << 8 |
                  static_cast<std::uint32_t>(b[9]) << 16;
  } else {
    frame.incompat_flags = 0;
    frame.compat_flags = 0;
    frame.seq = b[2];
    frame.sysid = b[3];
    frame.compid = b[4];
    frame.msgid = b[5];
  }
  frame.message = FindById(frame.msgid);
  frame.wire_length = length;
  frame.size = size;
  if ((incompat & ~kIncompatSigned) != 0) return FrameRead{FrameStatus::kIncompatible, size};
  if (frame.message == nullptr) return FrameRead{FrameStatus::kUnknownMessage, size};

  std::uint16_t crc = CrcAccumulate(bytes.substr(1, header - 1 + length), kCrcInit);
  crc = CrcAccumulate(frame.message->crc_extra, crc);
  const std::size_t at = header + length;
  const auto wire_crc = static_cast<std::uint16_t>(b[at] | b[at + 1] << 8);
  if (crc != wire_crc) return FrameRead{FrameStatus::kBadCrc, size};
  frame.payload.fill(0);
  std::memcpy(frame.payload.data(), b + header, length);
  return FrameRead{FrameStatus::kOk, size};
}

void SequenceTracker::Observe(std::uint8_t sysid, std::uint8_t compid, std::uint8_t seq) {
  SenderStats& s = senders_[SenderKey(sysid, compid)];
  if (s.frames > 0) {
    const auto skipped = static_cast<std::uint8_t>(seq - s.last_seq - 1);
    if (skipped != 0) {
      ++s.gaps;
      s.lost += skipped;
      lost_ += skipped;
    }
  }
  s.last_seq = seq;
  ++s.frames;
}

void FrameDecoder::Feed(std::string_view bytes, const FrameHandler& on_frame) {
  // Bytes kept from the last call and the new ones are read as one stream; without kept bytes
  // the new ones are read in place.
  std::string_view data = bytes;
  if (!pending_.empty()) {
    pending_.append(bytes.data(), bytes.size());
    data = pending_;
  }
  std::size_t pos = 0;
  while (pos < data.size()) {
    const std::size_t used = Step(data.substr(pos), on_frame);
    if (used == 0) break;  // a frame not yet complete
    pos += used;
  }
  std::string rest(data.substr(pos));  // copied before pending_, which `data` may view, changes
  pending_ = std::move(rest);
}

void FrameDecoder::Finish(const FrameHandler& on_frame) {
  // What is kept always starts at a start byte (Step skips anything else at once); each round
  // passes over that byte, so the loop ends.
  while (!pending_.empty()) {
    if (synced_) ++counters_.cut;
    std::string rest = pending_.substr(1);
    pending_.clear();
    SkipBytes(1);
    Feed(rest, on_frame);
  }
  synced_ = true;
}

std::size_t FrameDecoder::Step(std::string_view at, const FrameHandler& on_frame) {
  if (!IsStartByte(at[0])) {
    std::size_t next = 1;
    while (next < at.size() && !IsStartByte(at[next])) ++next;
    return SkipBytes(next);
  }
  const FrameRead r = ReadFrame(at, frame_);
  switch (r.status) {
    case FrameStatus::kNeedMore:
      return 0;
    case FrameStatus::kOk:
      return Deliver(at.substr(0, r.size), on_frame);
    case FrameStatus::kBadCrc:
      if (synced_) ++counters_.bad_crc;
      return SkipBytes(1);
    case FrameStatus::kUnknownMessage:
      if (!synced_) return SkipBytes(1);
      ++counters_.unknown_message;
      if (counters_.unknown_ids.size() < kMaxUnknownIds ||
          counters_.unknown_ids.count(frame_.msgid) != 0)
        ++counters_.unknown_ids[frame_.msgid];
      sequences_.Observe(frame_.sysid, frame_.compid, frame_.seq);
      return r.size;
    case FrameStatus::kIncompatible:
      if (!synced_) return SkipBytes(1);
      ++counters_.incompatible;
      return r.size;
    case FrameStatus::kNoFrame:
      break;
  }
  return SkipBytes(1);
}

std::size_t FrameDecoder::SkipBytes(std::size_t n) {
  synced_ = false;
  counters_.bytes_skipped += n;
  return n;
}

std::size_t FrameDecoder::Deliver(std::string_view frame_bytes, const FrameHandler& on_frame) {
  synced_ = true;  // the checksum matched: the framing is right, whatever the signature says
  if (frame_.is_signed() && check_ && !check_(frame_bytes)) {
    ++counters_.bad_signature;
    return frame_bytes.size();
  }
  ++counters_.frames_ok;
  if (frame_.version == 1) ++counters_.v1_frames;
  if (frame_.is_signed()) ++counters_.signed_frames;
  if (frame_.truncated()) ++counters_.truncated;
  sequences_.Observe(frame_.sysid, frame_.compid, frame_.seq);
  if (on_frame) on_frame(frame_);
  return frame_bytes.size();
}

}  // namespace odonata::mavlink
