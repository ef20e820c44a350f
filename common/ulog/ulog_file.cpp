#include "ulog/ulog_file.hpp"

#include "ulog/payload_cursor.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <unordered_map>
#include <utility>

namespace odonata::ulog {
namespace {

constexpr std::uint8_t kUlogMagic[7] = {0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35};
constexpr std::uint8_t kSyncMagic[8] = {0x2f, 0x73, 0x13, 0x20, 0x25, 0x0c, 0xbb, 0x12};
constexpr std::size_t kFileHeaderSize = 16;
constexpr std::size_t kMessageHeaderSize = 3;
constexpr std::size_t kFlagBitsSize = 40;
constexpr std::uint8_t kHighestKnownVersion = 1;
// Fields all the subscribed formats of one file may expand to. Real logs need some thousands;
// the bound keeps a hostile file (a 1-byte type nested 60000 times, per subscription) from
// taking gigabytes.
constexpr std::size_t kFieldBudget = 1'000'000;

std::string TypeLabel(std::uint8_t type) {
  if (type >= 0x21 && type < 0x7f) return std::string("'") + static_cast<char>(type) + "'";
  char hex[8];
  std::snprintf(hex, sizeof hex, "0x%02x", type);
  return hex;
}

std::string Hex(const std::array<std::uint8_t, 8>& bytes) {
  std::string s;
  char b[4];
  for (const std::uint8_t v : bytes) {
    std::snprintf(b, sizeof b, "%02x", v);
    s += b;
  }
  return s;
}

// One pass over the messages, in file order, filling `out`.
class MessageWalk {
 public:
  MessageWalk(std::string_view bytes, UlogFile& out) : bytes_(bytes), out_(out) {
    last_time_us_ = out_.start_time_us;
  }

  void Run() {
    std::size_t pos = kFileHeaderSize;
    while (Step(pos)) {
    }
    // Samples from appended data: none where there was none.
    if (!in_appended_)
      for (auto& s : out_.subscriptions) s.first_appended_sample = s.size();
  }

 private:
  // Reads the message at `pos` and advances past it; false at the end or at damage.
  bool Step(std::size_t& pos) {
    while (next_appended_ < appended_.size() && appended_[next_appended_] <= pos) {
      // From here on the data was appended after the log was first closed.
      if (!in_appended_)
        for (auto& s : out_.subscriptions) s.first_appended_sample = s.size();
      in_appended_ = true;
      ++next_appended_;
    }
    const std::size_t size = bytes_.size();
    const bool before_appended =
        next_appended_ < appended_.size() && appended_[next_appended_] <= size;
    if (pos >= size) {
      if (next_appended_ < appended_.size())
        Fail(size, "the flag bits place appended data at byte " +
                       std::to_string(appended_[next_appended_]) + ", past the end of the " +
                       std::to_string(size) + "-byte file");
      return false;
    }
    // Messages of the log as first written end where appended data begins.
    const std::size_t end = before_appended ? appended_[next_appended_] : size;
    const std::size_t left = end - pos;
    const auto* at = reinterpret_cast<const std::uint8_t*>(bytes_.data()) + pos;
    if (left < kMessageHeaderSize) {
      if (before_appended) return SkipToAppended(pos, end, "a cut message header");
      Fail(pos, "message header at byte " + std::to_string(pos) + " is cut: only " +
                    std::to_string(left) + " bytes left");
      return false;
    }
    const std::size_t payload_size = ReadUnsignedLE(at, 2);
    const std::uint8_t type = at[2];
    if (type == 0 && std::all_of(at, at + left, [](std::uint8_t b) { return b == 0; })) {
      // Zeros where the writer reserved room it never filled (before appended data, or at the
      // end of a file the autopilot preallocated): no message, nothing lost.
      out_.notes.push_back(std::to_string(left) + " zero bytes at byte " + std::to_string(pos) +
                           (before_appended
                                ? " before the data appended at byte " + std::to_string(end)
                                : std::string(" at the end")) +
                           ": skipped");
      pos = end;
      return true;
    }
    if (payload_size > left - kMessageHeaderSize) {
      if (before_appended)
        return SkipToAppended(pos, end, "a message of type " + TypeLabel(type) + " cut");
      Fail(pos, "message of type " + TypeLabel(type) + " at byte " + std::to_string(pos) +
                    " claims " + std::to_string(payload_size) + " bytes, only " +
                    std::to_string(left - kMessageHeaderSize) + " left");
      return false;
    }
    try {
      Dispatch(type, bytes_.substr(pos + kMessageHeaderSize, payload_size), pos);
    } catch (const MessageDamage& d) {
      Fail(pos, "message of type " + TypeLabel(type) + " at byte " + std::to_string(pos) + ": " +
                    d.what);
      return false;
    }
    ++out_.message_counts[static_cast<char>(type)];
    if (in_appended_) ++out_.appended_messages;
    pos += kMessageHeaderSize + payload_size;
    return true;
  }

  // The log was cut mid-message and data appended after it (as the spec has appenders do): the
  // cut message is dropped and reading goes on where the appended data starts.
  bool SkipToAppended(std::size_t& pos, std::size_t end, const std::string& what) {
    out_.notes.push_back(what + " at byte " + std::to_string(pos) +
                         " before the data appended at byte " + std::to_string(end) + ": " +
                         std::to_string(end - pos) + " bytes skipped");
    pos = end;
    return true;
  }

  void Fail(std::size_t offset, std::string what) {
    out_.problem = std::move(what);
    out_.problem_offset = offset;
  }

  void Dispatch(std::uint8_t type, std::string_view payload, std::size_t pos) {
    PayloadCursor in(payload);
    switch (type) {
      case 'B':
        return FlagBitsMessage(in, payload.size(), pos);
      case 'F':
        return FormatMessage(payload);
      case 'I': {
        NamedValue v = TakeNamedValue(in);
        out_.info[v.name] = std::move(v.value);
        return;
      }
      case 'M':
        return MultiInfoMessage(in);
      case 'P':
        return ParameterMessage(in);
      case 'Q':
        return DefaultParameterMessage(in);
      case 'A':
        return AddLoggedMessage(in, pos);
      case 'R':
        return RemoveLoggedMessage(in);
      case 'D':
        return DataMessage(in);
      case 'L':
      case 'C':
        return LoggingMessage(in, type == 'C');
      case 'S':
        return SyncMessage(in);
      case 'O':
        return DropoutMessage(in);
      case 0:
        // pyulog, PX4's reader, takes type 0 for corruption too: no writer emits it.
        throw MessageDamage{"type 0 is no ULog message (the bytes are corrupt)"};
      default:
        // The spec has readers skip what they do not know: a later format version's messages.
        ++out_.unknown_message_counts[static_cast<char>(type)];
        return;
    }
  }

  void FlagBitsMessage(PayloadCursor& in, std::size_t payload_size, std::size_t pos) {
    if (pos != kFileHeaderSize || out_.flags.present)
      throw MessageDamage{
          "the flag bits message must be the first message, right after the "
          "header"};
    if (payload_size < kFlagBitsSize)
      throw MessageDamage{"the flag bits message has " + std::to_string(payload_size) +
                          " bytes, it needs " + std::to_string(kFlagBitsSize)};
    FlagBits& f = out_.flags;
    for (auto& b : f.compat) b = in.U8("compat_flags");
    for (auto& b : f.incompat) b = in.U8("incompat_flags");
    for (auto& o : f.appended_offsets) o = in.U64("appended_offsets");
    f.present = true;
    if (payload_size > kFlagBitsSize)
      out_.notes.push_back("the flag bits message has " +
                           std::to_string(payload_size - kFlagBitsSize) +
                           " bytes more than this reader knows; they are ignored");
    // Only bit 0 of incompat_flags[0] (data appended) is defined: any other marks a change that
    // breaks readers, which the spec says must refuse the log.
    auto unknown_incompat = f.incompat;
    unknown_incompat[0] &= 0xfe;
    if (std::any_of(unknown_incompat.begin(), unknown_incompat.end(),
                    [](std::uint8_t b) { return b != 0; }))
      throw MessageDamage{"unknown incompatible flag bits are set (incompat_flags " +
                          Hex(f.incompat) + "): the log uses changes this reader cannot parse"};
    auto unknown_compat = f.compat;
    unknown_compat[0] &= 0xfe;
    if (std::any_of(unknown_compat.begin(), unknown_compat.end(),
                    [](std::uint8_t b) { return b != 0; }))
      out_.notes.push_back("unknown compatible flag bits are set (compat_flags " + Hex(f.compat) +
                           "); ignored, as the spec allows");
    const std::size_t end = pos + kMessageHeaderSize + payload_size;
    for (const std::uint64_t o : f.appended_offsets) {
      if (o == 0) continue;
      if (!f.has_appended_data()) {
        out_.notes.push_back("appended offsets are set without the data-appended flag; ignored");
        break;
      }
      if (o < end)
        throw MessageDamage{"appended data is placed at byte " + std::to_string(o) +
                            ", inside the header or this message"};
      appended_.push_back(o);
    }
    std::sort(appended_.begin(), appended_.end());
    appended_.erase(std::unique(appended_.begin(), appended_.end()), appended_.end());
    if (f.has_appended_data() && appended_.empty())
      out_.notes.push_back("the data-appended flag is set but no appended offset");
  }

  void FormatMessage(std::string_view text) {
    Format f;
    try {
      f = ParseFormat(text);
    } catch (const UlogError& e) {
      throw MessageDamage{e.what()};
    }
    const auto [it, added] = format_texts_.emplace(f.name, std::string(text));
    if (!added) {
      // A layout may already have been made from the first definition: two would be ambiguous.
      if (it->second != text)
        throw MessageDamage{"format '" + f.name + "' is defined a second time, differently"};
      return;
    }
    out_.formats.emplace(f.name, std::move(f));
  }

  void MultiInfoMessage(PayloadCursor& in) {
    const bool continued = in.U8("is_continued") != 0;
    NamedValue v = TakeNamedValue(in);
    auto& values = out_.multi_info[v.name];
    // A continuation without a value to continue starts one, as PX4's reader does.
    if (continued && !values.empty())
      AppendContinuation(values.back(), v.value.bytes);
    else
      values.push_back(std::move(v.value));
  }

  void ParameterMessage(PayloadCursor& in) {
    NamedValue v = TakeNamedValue(in);
    RequireNumber(v);
    // The definitions section ends at the first subscription or log message: a parameter after
    // it is a change in flight.
    if (!in_data_section_)
      out_.initial_parameters[v.name] = std::move(v.value);
    else
      out_.changed_parameters.push_back(
          ParameterChange{last_time_us_, std::move(v.name), std::move(v.value)});
  }

  void DefaultParameterMessage(PayloadCursor& in) {
    const std::uint8_t types = in.U8("default_types");
    NamedValue v = TakeNamedValue(in);
    RequireNumber(v);
    out_.default_parameters.push_back(
        DefaultParameter{types, std::move(v.name), std::move(v.value)});
  }

  void AddLoggedMessage(PayloadCursor& in, std::size_t pos) {
    in_data_section_ = true;
    Subscription s;
    s.multi_id = in.U8("multi_id");
    s.msg_id = in.U16("msg_id");
    s.topic = std::string(in.Rest());
    s.subscribed_at = pos;
    if (s.topic.empty()) throw MessageDamage{"the subscription names no topic"};
    if (const auto it = by_msg_id_.find(s.msg_id); it != by_msg_id_.end()) {
      const Subscription& old = out_.subscriptions[it->second];
      if (old.topic == s.topic && old.multi_id == s.multi_id) return;  // said again: harmless
      throw MessageDamage{"msg_id " + std::to_string(s.msg_id) + " subscribes '" + s.topic +
                          "' but is already '" + old.topic + "'"};
    }
    auto& layout = layouts_[s.topic];
    if (!layout) {
      try {
        layout = std::make_shared<const Layout>(ResolveLayout(s.topic, out_.formats, budget_));
      } catch (const UlogError& e) {
        layouts_.erase(s.topic);
        throw MessageDamage{"subscription of '" + s.topic + "': " + e.what()};
      }
    }
    s.layout = layout;
    by_msg_id_.emplace(s.msg_id, out_.subscriptions.size());
    out_.subscriptions.push_back(std::move(s));
  }

  void RemoveLoggedMessage(PayloadCursor& in) {
    const std::uint16_t msg_id = in.U16("msg_id");
    if (const auto it = by_msg_id_.find(msg_id); it != by_msg_id_.end())
      out_.subscriptions[it->second].removed = true;
    else
      out_.notes.push_back("an unsubscription of msg_id " + std::to_string(msg_id) +
                           ", which was never subscribed");
  }

  void DataMessage(PayloadCursor& in) {
    const std::uint16_t msg_id = in.U16("msg_id");
    const auto it = by_msg_id_.find(msg_id);
    if (it == by_msg_id_.end())
      throw MessageDamage{"data for msg_id " + std::to_string(msg_id) +
                          ", which no subscription ('A') defines"};
    Subscription& s = out_.subscriptions[it->second];
    const Layout& layout = *s.layout;
    const std::string_view data = in.Rest();
    if (data.size() < layout.logged_size || data.size() > layout.size)
      throw MessageDamage{"data of '" + s.topic + "' (msg_id " + std::to_string(msg_id) + ") has " +
                          std::to_string(data.size()) + " bytes, its format " +
                          (data.size() < layout.logged_size
                               ? "needs at least " + std::to_string(layout.logged_size)
                               : "has only " + std::to_string(layout.size))};
    const auto* p = reinterpret_cast<const std::uint8_t*>(data.data());
    s.data.insert(s.data.end(), p, p + layout.logged_size);
    const std::uint64_t t = ReadUnsignedLE(p + layout.timestamp_offset, 8);
    s.timestamps_us.push_back(t);
    last_time_us_ = std::max(last_time_us_, t);
  }

  void LoggingMessage(PayloadCursor& in, bool tagged) {
    in_data_section_ = true;
    LogMessage m;
    m.level = in.U8("log_level");
    if (tagged) m.tag = in.U16("tag");
    m.timestamp_us = in.U64("timestamp");
    m.text = std::string(in.Rest());
    out_.log_messages.push_back(std::move(m));
  }

  void SyncMessage(PayloadCursor& in) {
    const std::string_view magic = in.Take(sizeof kSyncMagic, "the sync magic");
    if (std::memcmp(magic.data(), kSyncMagic, sizeof kSyncMagic) != 0)
      throw MessageDamage{"the sync message does not hold the sync magic"};
    ++out_.sync_count;
  }

  void DropoutMessage(PayloadCursor& in) {
    const std::uint16_t ms = in.U16("duration");
    out_.dropouts.push_back(Dropout{last_time_us_, ms});
    out_.dropout_total_ms += ms;
  }

  std::string_view bytes_;
  UlogFile& out_;
  bool in_data_section_ = false;
  std::uint64_t last_time_us_ = 0;
  std::unordered_map<std::uint16_t, std::size_t> by_msg_id_;
  std::map<std::string, std::string> format_texts_;
  std::map<std::string, std::shared_ptr<const Layout>> layouts_;
  std::size_t budget_ = kFieldBudget;
  std::vector<std::uint64_t> appended_;  // sorted, distinct
  std::size_t next_appended_ = 0;
  bool in_appended_ = false;
};

}  // namespace

const Subscription* UlogFile::FindSubscription(std::uint16_t msg_id) const {
  for (const auto& s : subscriptions)
    if (s.msg_id == msg_id) return &s;
  return nullptr;
}

const Subscription* UlogFile::FindTopic(std::string_view topic, std::uint8_t multi_id) const {
  for (const auto& s : subscriptions)
    if (s.topic == topic && s.multi_id == multi_id) return &s;
  return nullptr;
}

std::size_t UlogFile::MessageCount(char type) const {
  const auto it = message_counts.find(type);
  return it == message_counts.end() ? 0 : it->second;
}

UlogFile Parse(std::string_view bytes, const std::string& source_name) {
  if (bytes.empty()) throw UlogError(source_name + ": empty, not a ULog file");
  if (bytes.size() < kFileHeaderSize ||
      std::memcmp(bytes.data(), kUlogMagic, sizeof kUlogMagic) != 0) {
    const bool magic_prefix =
        std::memcmp(bytes.data(), kUlogMagic, std::min(bytes.size(), sizeof kUlogMagic)) == 0;
    throw UlogError(source_name + ": " +
                    (magic_prefix ? "only " + std::to_string(bytes.size()) +
                                        " bytes, shorter than the 16-byte ULog header"
                                  : std::string("not a ULog file (it does not start with the "
                                                "ULog magic 'ULog' 01 12 35)")));
  }
  UlogFile f;
  f.source = source_name;
  f.file_size = bytes.size();
  const auto* b = reinterpret_cast<const std::uint8_t*>(bytes.data());
  f.version = b[7];
  f.start_time_us = ReadUnsignedLE(b + 8, 8);
  if (f.version > kHighestKnownVersion)
    f.notes.push_back("file format version " + std::to_string(f.version) +
                      " is newer than this reader's; read as version 1, as the spec asks");
  MessageWalk(bytes, f).Run();
  return f;
}

UlogFile Parse(const std::vector<std::uint8_t>& bytes, const std::string& source_name) {
  return Parse(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
               source_name);
}

UlogFile Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw UlogError(path + ": cannot open file (" + std::strerror(errno) + ")");
  const std::streamoff size = in.tellg();
  if (size < 0) throw UlogError(path + ": cannot tell the file's size");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), size)) throw UlogError(path + ": cannot read file");
  return Parse(bytes, path);
}

UlogFile ParseStrict(std::string_view bytes, const std::string& source_name) {
  UlogFile f = Parse(bytes, source_name);
  if (!f.complete()) throw UlogError(source_name + ": " + f.problem);
  return f;
}

UlogFile ReadStrict(const std::string& path) {
  UlogFile f = Read(path);
  if (!f.complete()) throw UlogError(path + ": " + f.problem);
  return f;
}

}  // namespace odonata::ulog
