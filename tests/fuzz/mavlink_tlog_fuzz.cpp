// Fuzz harness: the MAVLink telemetry-log reader and its signals, and the frame decoder on the
// same bytes. Damage in a log must end in the file's `problem` (the walk resynchronising on the
// next verified record), what is no telemetry log in odonata::mavlink::TlogError, a signal that
// cannot be had in std::invalid_argument; the decoder must count what it drops, never throw, and
// decode a stream split anywhere as it decodes it whole: never a crash, undefined behaviour or
// unbounded memory.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mavlink/frame_decoder.hpp"
#include "mavlink/tlog_file.hpp"
#include "mavlink/tlog_signals.hpp"

namespace {

namespace mav = odonata::mavlink;

void Check(bool ok) {
  if (!ok) __builtin_trap();
}

// What a decoder delivered and counted.
struct Decoded {
  std::vector<std::pair<std::uint32_t, std::uint8_t>> frames;  // msgid, seq
  mav::DecoderCounters counters;
  std::size_t lost = 0;
};

// `bytes` through a decoder, fed in pieces of `piece` bytes after a first one of `first`.
Decoded Decode(std::string_view bytes, std::size_t first, std::size_t piece) {
  Decoded out;
  mav::FrameDecoder decoder;
  const mav::FrameDecoder::FrameHandler keep = [&out](const mav::Frame& f) {
    Check(f.message != nullptr && f.size <= mav::kMaxFrameSize);
    Check(f.wire_length <= mav::kMaxPayloadSize);
    // Zero-extended: nothing of an earlier frame shows past this one's payload.
    for (std::size_t i = f.wire_length; i < f.payload.size(); ++i) Check(f.payload[i] == 0);
    out.frames.emplace_back(f.msgid, f.seq);
  };
  std::size_t at = std::min(first, bytes.size());
  decoder.Feed(bytes.substr(0, at), keep);
  while (at < bytes.size()) {
    decoder.Feed(bytes.substr(at, piece), keep);
    at += piece;
  }
  decoder.Finish(keep);
  out.counters = decoder.counters();
  out.lost = decoder.sequences().lost();
  return out;
}

void CheckDecoder(std::string_view bytes) {
  const Decoded whole = Decode(bytes, bytes.size(), 1);
  const mav::DecoderCounters& c = whole.counters;
  Check(c.frames_ok == whole.frames.size());
  Check(c.bytes_skipped <= bytes.size());
  // Every byte is in one frame read whole (delivered, or dropped as unknown, incompatible or
  // badly signed; 8 bytes at least) or skipped.
  Check((c.frames_ok + c.unknown_message + c.incompatible + c.bad_signature) * 8 +
            c.bytes_skipped <=
        bytes.size());
  const Decoded split = Decode(bytes, bytes.size() / 3, 7);
  const mav::DecoderCounters& s = split.counters;
  Check(split.frames == whole.frames);
  Check(s.frames_ok == c.frames_ok && s.v1_frames == c.v1_frames &&
        s.signed_frames == c.signed_frames && s.truncated == c.truncated &&
        s.bad_crc == c.bad_crc && s.unknown_message == c.unknown_message &&
        s.incompatible == c.incompatible && s.cut == c.cut && s.bytes_skipped == c.bytes_skipped);
  Check(split.lost == whole.lost);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  CheckDecoder(bytes);
  try {
    const mav::TlogFile file = mav::Parse(bytes, "fuzz");
    Check(file.complete() == file.problem.empty());
    Check(file.complete() == (file.damage_count == 0));
    Check(file.problem_offset <= size);
    Check(file.bytes_skipped <= size);
    Check(file.file_size == size);
    // A record is an 8-byte timestamp and a frame of at least 8 bytes.
    Check(file.records * 16 <= size);
    std::size_t kept = 0;
    for (const mav::MessageSeries& s : file.series) {
      Check(s.message != nullptr && s.size() > 0);
      Check(s.payloads.size() == s.size() * s.message->length);
      Check(s.truncated <= s.size());
      kept += s.size();
    }
    Check(kept + file.unknown_frames + file.incompatible == file.records);
    std::size_t counted = 0;
    for (const auto& [id, n] : file.frame_counts) counted += n;
    Check(counted <= file.records);
    Check(std::is_sorted(file.series.begin(), file.series.end(),
                         [](const mav::MessageSeries& a, const mav::MessageSeries& b) {
                           return a.message->name < b.message->name;
                         }));
    const std::vector<mav::SignalInfo> signals = mav::ListSignals(file);
    for (std::size_t i = 0; i < signals.size(); i += 1 + signals.size() / 4) {
      const odonata::timeseries::TimedSignal s = mav::Extract(file, signals[i].name);
      Check(s.t_s.size() == s.values.size() && s.values.size() == signals[i].samples);
      Check(std::is_sorted(s.t_s.begin(), s.t_s.end()));
      Check(s.interpolation == signals[i].interpolation);
    }
    (void)mav::Extract(file, "NO@1:2.such[0]");
  } catch (const mav::TlogError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
