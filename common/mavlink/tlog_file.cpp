#include "mavlink/tlog_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <tuple>
#include <utility>

namespace odonata::mavlink {
namespace {

// Notes beyond this are left out: a hostile file could otherwise make one per record.
constexpr std::size_t kMaxTlogNotes = 100;

std::uint64_t TlogTimeAt(std::string_view bytes, std::size_t pos) {
  return TlogStampAt(bytes.data() + pos);
}

bool PlausibleTlogTime(std::uint64_t t_us) {
  return t_us >= kEarliestTlogTimeUs && t_us < kLatestTlogTimeUs;
}

bool StartsFrame(char c) {
  const auto b = static_cast<std::uint8_t>(c);
  return b == kStartV1 || b == kStartV2;
}

std::string AtByte(std::size_t offset) { return "at byte " + std::to_string(offset); }

// "ATTITUDE (id 30)", or "message id 178" for one the table does not know.
std::string FrameLabel(const Frame& f) {
  if (f.message != nullptr) return f.message->name + " (id " + std::to_string(f.msgid) + ")";
  return "message id " + std::to_string(f.msgid);
}

// Counts `id` in `counts`, one by one for the first kMaxUnknownIds distinct ids.
void CountId(std::map<std::uint32_t, std::size_t>& counts, std::uint32_t id) {
  if (counts.size() < kMaxUnknownIds || counts.count(id) != 0) ++counts[id];
}

// One pass over the records, in file order, filling `out`.
class TlogWalk {
 public:
  TlogWalk(std::string_view bytes, TlogFile& out) : bytes_(bytes), out_(out) {}

  void Run() {
    std::size_t pos = 0;
    while (pos < bytes_.size()) pos = Step(pos);
    std::sort(out_.series.begin(), out_.series.end(),
              [](const MessageSeries& a, const MessageSeries& b) {
                return std::tie(a.message->name, a.sysid, a.compid) <
                       std::tie(b.message->name, b.sysid, b.compid);
              });
    if (out_.incompatible > 0)
      Note(std::to_string(out_.incompatible) +
           " frames have MAVLink 2 incompat flags other than signing: dropped, as the spec says");
    if (time_reversals_ > 0)
      Note(std::to_string(time_reversals_) +
           " records are timed earlier than the record before them (the ground station's clock "
           "went back)");
  }

 private:
  // Reads the record at `pos` and returns where the next one starts.
  std::size_t Step(std::size_t pos) {
    const std::size_t left = bytes_.size() - pos;
    if (left <= kTlogTimestampSize)
      return Cut(pos, "the last record, " + AtByte(pos) + ", is cut: only " + std::to_string(left) +
                          " bytes are left of its timestamp");
    const std::uint64_t t_us = TlogTimeAt(bytes_, pos);
    if (!PlausibleTlogTime(t_us))
      return Resync(pos, "its timestamp, " + std::to_string(t_us) +
                             " microseconds since 1970, is no date between 2000 and 2100");
    if (!StartsFrame(bytes_[pos + kTlogTimestampSize])) {
      char byte[8];
      std::snprintf(
          byte, sizeof byte, "0x%02x",
          static_cast<unsigned>(static_cast<std::uint8_t>(bytes_[pos + kTlogTimestampSize])));
      return Resync(pos, "its frame starts with " + std::string(byte) +
                             ", no MAVLink start byte (0xFD, 0xFE)");
    }
    const FrameRead r = ReadFrame(bytes_.substr(pos + kTlogTimestampSize), frame_);
    switch (r.status) {
      case FrameStatus::kNeedMore:
        return Cut(pos, "the last record, " + AtByte(pos) + ", is cut: its frame needs " +
                            std::to_string(r.size) + " bytes, only " +
                            std::to_string(left - kTlogTimestampSize) + " are left");
      case FrameStatus::kBadCrc:
        ++out_.bad_crc;
        return Resync(pos, "its " + FrameLabel(frame_) + " frame from " +
                               std::to_string(frame_.sysid) + ":" + std::to_string(frame_.compid) +
                               " fails its checksum");
      case FrameStatus::kNoFrame:  // the start byte was checked
        return Resync(pos, "no frame");
      case FrameStatus::kOk:
        Keep(t_us);
        out_.sequences.Observe(frame_.sysid, frame_.compid, frame_.seq);
        break;
      case FrameStatus::kUnknownMessage:
        ++out_.unknown_frames;
        CountId(out_.unknown_counts, frame_.msgid);
        out_.sequences.Observe(frame_.sysid, frame_.compid, frame_.seq);
        break;
      case FrameStatus::kIncompatible:
        ++out_.incompatible;
        break;
    }
    CountRecord(t_us);
    return pos + kTlogTimestampSize + r.size;
  }

  void CountRecord(std::uint64_t t_us) {
    if (out_.records == 0) out_.first_time_us = t_us;
    if (out_.records > 0 && t_us < out_.last_time_us) ++time_reversals_;
    out_.last_time_us = t_us;
    ++out_.records;
    CountId(out_.frame_counts, frame_.msgid);
    if (frame_.version == 1) ++out_.v1_frames;
    if (frame_.is_signed()) ++out_.signed_frames;
  }

  // Keeps the frame just read, a known message whose checksum matched.
  void Keep(std::uint64_t t_us) {
    const auto key = std::make_tuple(frame_.msgid, frame_.sysid, frame_.compid);
    auto [it, added] = index_.try_emplace(key, out_.series.size());
    if (added) {
      MessageSeries s;
      s.message = frame_.message;
      s.sysid = frame_.sysid;
      s.compid = frame_.compid;
      out_.series.push_back(std::move(s));
    }
    MessageSeries& s = out_.series[it->second];
    s.times_us.push_back(t_us);
    const std::uint8_t* p = frame_.payload.data();
    s.payloads.insert(s.payloads.end(), p, p + s.message->length);
    if (frame_.truncated()) ++s.truncated;
  }

  // Where a record can be verified at `pos`: a plausible timestamp and a start byte.
  bool HeadAt(std::size_t pos) const {
    return pos + kTlogTimestampSize < bytes_.size() && PlausibleTlogTime(TlogTimeAt(bytes_, pos)) &&
           StartsFrame(bytes_[pos + kTlogTimestampSize]);
  }

  // Whether the walk may resume at `pos` (see the header): the head, then a known frame whose
  // checksum matches, a frame the end of the file cuts, or an unknown one followed by a head.
  bool VerifiedAt(std::size_t pos) {
    if (!HeadAt(pos)) return false;
    const FrameRead r = ReadFrame(bytes_.substr(pos + kTlogTimestampSize), probe_);
    switch (r.status) {
      case FrameStatus::kOk:
      case FrameStatus::kNeedMore:
        return true;
      case FrameStatus::kUnknownMessage:
      case FrameStatus::kIncompatible: {
        const std::size_t next = pos + kTlogTimestampSize + r.size;
        return next == bytes_.size() || HeadAt(next);
      }
      case FrameStatus::kBadCrc:
      case FrameStatus::kNoFrame:
        break;
    }
    return false;
  }

  // Bytes at `pos` that are no record (`why`): skipped to the next verified record.
  std::size_t Resync(std::size_t pos, const std::string& why) {
    std::size_t next = pos + 1;
    while (next < bytes_.size() && !VerifiedAt(next)) ++next;
    Damage(pos, std::to_string(next - pos) + " bytes " + AtByte(pos) + " are no record (" + why +
                    "): skipped to " +
                    (next == bytes_.size() ? std::string("the end of the file")
                                           : "the next record, " + AtByte(next)));
    out_.bytes_skipped += next - pos;
    return next;
  }

  std::size_t Cut(std::size_t pos, std::string what) {
    Damage(pos, std::move(what));
    out_.bytes_skipped += bytes_.size() - pos;
    return bytes_.size();
  }

  void Damage(std::size_t offset, std::string what) {
    ++out_.damage_count;
    if (!out_.problem.empty()) return;
    out_.problem = std::move(what);
    out_.problem_offset = offset;
  }

  void Note(std::string what) {
    if (out_.notes.size() < kMaxTlogNotes)
      out_.notes.push_back(std::move(what));
    else if (out_.notes.size() == kMaxTlogNotes)
      out_.notes.push_back("further notes are left out");
  }

  std::string_view bytes_;
  TlogFile& out_;
  Frame frame_;  // the record's frame
  Frame probe_;  // a frame looked at while resynchronising
  std::map<std::tuple<std::uint32_t, std::uint8_t, std::uint8_t>, std::size_t> index_;
  std::size_t time_reversals_ = 0;
};

[[noreturn]] void ThrowTlogTooLarge(const std::string& source, std::uint64_t size) {
  throw TlogError(source + ": " + std::to_string(size) + " bytes, more than the " +
                  std::to_string(kMaxTlogBytes) + " bytes this reader takes");
}

}  // namespace

const MessageSeries* TlogFile::Find(std::string_view message, std::uint8_t sysid,
                                    std::uint8_t compid) const {
  for (const MessageSeries& s : series)
    if (s.message->name == message && s.sysid == sysid && s.compid == compid) return &s;
  return nullptr;
}

const MessageSeries* TlogFile::FindMain(std::string_view message) const {
  const MessageSeries* best = nullptr;
  // The series are sorted by sender: the first of the most frames has the lowest sysid:compid.
  for (const MessageSeries& s : series)
    if (s.message->name == message && (best == nullptr || s.size() > best->size())) best = &s;
  return best;
}

std::size_t TlogFile::FrameCount(std::string_view message) const {
  std::size_t n = 0;
  for (const MessageSeries& s : series)
    if (s.message->name == message) n += s.size();
  return n;
}

bool LooksLikeTlog(std::string_view head) {
  return head.size() > kTlogTimestampSize && PlausibleTlogTime(TlogTimeAt(head, 0)) &&
         StartsFrame(head[kTlogTimestampSize]);
}

TlogFile Parse(std::string_view bytes, const std::string& source) {
  if (bytes.empty()) throw TlogError(source + ": empty, not a MAVLink telemetry log");
  if (bytes.size() > kMaxTlogBytes) ThrowTlogTooLarge(source, bytes.size());
  if (!LooksLikeTlog(bytes))
    throw TlogError(source +
                    ": not a MAVLink telemetry log (it does not start with a record: an 8-byte "
                    "big-endian timestamp between 2000 and 2100, then a frame's start byte 0xFD "
                    "or 0xFE)");
  TlogFile f;
  f.source = source;
  f.file_size = bytes.size();
  TlogWalk(bytes, f).Run();
  return f;
}

TlogFile Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw TlogError(path + ": cannot open file (" + std::strerror(errno) + ")");
  const std::streamoff size = in.tellg();
  if (size < 0) throw TlogError(path + ": cannot tell the file's size");
  if (static_cast<std::uint64_t>(size) > kMaxTlogBytes)
    ThrowTlogTooLarge(path, static_cast<std::uint64_t>(size));
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (size > 0 && !in.read(bytes.data(), size)) throw TlogError(path + ": cannot read file");
  return Parse(bytes, path);
}

}  // namespace odonata::mavlink
