#include "dataflash/dataflash_file.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <utility>

namespace odonata::dataflash {
namespace {

// Notes beyond this are left out: a hostile file could otherwise make one per record.
constexpr std::size_t kMaxNotes = 100;

std::string AtByte(std::size_t offset) { return "at byte " + std::to_string(offset); }

// "'AHR2' (type 141, 45 bytes)"
std::string Describe(const MessageFormat& f) {
  return "'" + f.name + "' (type " + std::to_string(f.type) + ", " + std::to_string(f.length) +
         " bytes)";
}

FieldKind KindOf(const Field& f) { return LookupFormatChar(f.type)->kind; }

// An integer field holding 0…255 (a type number, a UNIT or MULT id), or nullopt.
std::optional<std::uint8_t> ByteValue(const std::uint8_t* payload, const Field& f) {
  if (KindOf(f) != FieldKind::kInteger) return std::nullopt;
  const double v = RawValue(payload, f);
  if (v < 0.0 || v > 255.0) return std::nullopt;
  return static_cast<std::uint8_t>(v);
}

// What a record of a type is to the walk, besides data: the unit tables.
enum class RecordRole : std::uint8_t { kData, kFmtu, kUnit, kMult };

// One pass over the records, in file order, filling `out`.
class RecordWalk {
 public:
  explicit RecordWalk(DataflashFile& out)
      : out_(out),
        data_(reinterpret_cast<const std::uint8_t*>(out.bytes.data())),
        size_(out.bytes.size()) {}

  void Run() {
    AddFormat(FmtFormat());
    std::size_t pos = 0;
    while (pos < size_) pos = Step(pos);
  }

 private:
  // Reads what starts at `pos` and returns where the next record may start.
  std::size_t Step(std::size_t pos) {
    const std::size_t left = size_ - pos;
    if (data_[pos] != kRecordHead1 || (left > 1 && data_[pos + 1] != kRecordHead2))
      return SkipNonRecord(pos);
    if (left < kRecordHeaderSize) {
      Damage(pos, "the last record's header, " + AtByte(pos) + ", is cut: only " +
                      std::to_string(left) + " bytes are left");
      out_.bytes_skipped += left;
      return size_;
    }
    const std::uint8_t type = data_[pos + 2];
    const auto it = out_.formats.find(type);
    if (it == out_.formats.end()) return SkipUnknownType(pos, type);
    const std::size_t length = it->second.length;
    if (length > left) {
      Damage(pos, "the last record, " + Describe(it->second) + " " + AtByte(pos) +
                      ", is cut: only " + std::to_string(left) + " bytes are left");
      out_.bytes_skipped += left;
      return size_;
    }
    ++out_.record_counts[type];
    Dispatch(it->second, pos);
    return pos + length;
  }

  // Bytes that are no record header: skipped to the next header, unless they are the padding
  // some boards leave after the last record.
  std::size_t SkipNonRecord(std::size_t pos) {
    const std::size_t next = NextHead(pos + 1);
    const std::size_t n = next - pos;
    const auto* begin = data_ + pos;
    const auto* end = data_ + size_;
    if (next == size_ && (std::all_of(begin, end, [](std::uint8_t b) { return b == 0x00; }) ||
                          std::all_of(begin, end, [](std::uint8_t b) { return b == 0xff; }))) {
      Note(std::to_string(n) + " bytes of " + (*begin == 0 ? "0x00" : "0xff") +
           " padding at the end, from byte " + std::to_string(pos) + ": no records");
      return size_;
    }
    Damage(pos, std::to_string(n) + " bytes " + AtByte(pos) +
                    " are no record (no header 0xA3 0x95): skipped to " +
                    (next == size_ ? std::string("the end of the file")
                                   : "the next record header, " + AtByte(next)));
    out_.bytes_skipped += n;
    return next;
  }

  // A header whose type no FMT has described: its length is unknown, so the walk resumes at the
  // next header.
  std::size_t SkipUnknownType(std::size_t pos, std::uint8_t type) {
    ++out_.unknown_type_counts[type];
    const std::size_t next = NextHead(pos + 2);
    Damage(pos, "a record of type " + std::to_string(type) + " " + AtByte(pos) +
                    " has no FMT record, so its length is unknown: skipped to " +
                    (next == size_ ? std::string("the end of the file")
                                   : "the next record header, " + AtByte(next)));
    out_.bytes_skipped += next - pos;
    return next;
  }

  // The first 0xA3 0x95 at or after `from` (a lone 0xA3 as the last byte: a cut header), or the
  // end.
  std::size_t NextHead(std::size_t from) const {
    constexpr char kHead[] = {'\xA3', '\x95'};
    const std::size_t at = std::string_view(out_.bytes).find(std::string_view(kHead, 2), from);
    if (at != std::string_view::npos) return at;
    if (from < size_ && data_[size_ - 1] == kRecordHead1) return size_ - 1;
    return size_;
  }

  void Dispatch(const MessageFormat& f, std::size_t pos) {
    const std::uint8_t* payload = data_ + pos + kRecordHeaderSize;
    if (MessageRecords* kept = kept_[f.type]) kept->offsets.push_back(pos);
    if (f.type == kFmtType) return FmtRecord(payload, pos);
    switch (role_[f.type]) {
      case RecordRole::kFmtu:
        return FmtuRecord(f, payload);
      case RecordRole::kUnit:
        return UnitRecord(f, payload);
      case RecordRole::kMult:
        return MultRecord(f, payload);
      case RecordRole::kData:
        return;
    }
  }

  void FmtRecord(const std::uint8_t* payload, std::size_t pos) {
    const auto chars = [payload](std::size_t at, std::size_t n) {
      return CString(std::string_view(reinterpret_cast<const char*>(payload) + at, n));
    };
    const std::uint8_t type = payload[0];
    const std::size_t length = payload[1];
    MessageFormat f =
        MakeFormat(type, chars(2, 4), length < kRecordHeaderSize ? kRecordHeaderSize : length,
                   chars(6, 16), chars(22, 64));
    f.defined_at = pos;
    if (type == kFmtType) {
      // FMT's own layout is fixed: a file redefining it could not be framed.
      if (length != kFmtLength || f.format != "BBnNZ")
        Note("the FMT record " + AtByte(pos) + " redefines FMT itself as \"" + f.format + "\", " +
             std::to_string(length) + " bytes: ignored");
      return;
    }
    if (length < kRecordHeaderSize) {
      Damage(pos, "the FMT record " + AtByte(pos) + " gives '" + f.name + "' (type " +
                      std::to_string(type) + ") a length of " + std::to_string(length) +
                      " bytes, shorter than a record header: its records cannot be framed");
      return;
    }
    const auto old = out_.formats.find(type);
    if (old != out_.formats.end()) {
      const MessageFormat& o = old->second;
      if (o.name == f.name && o.length == f.length && o.format == f.format && o.labels == f.labels)
        return;  // written again, as ArduPilot does when it starts a new log file
      const auto n = out_.record_counts.find(type);
      if (n != out_.record_counts.end() && n->second > 0) {
        Damage(pos, "the FMT record " + AtByte(pos) + " redefines " + Describe(o) + ", after " +
                        std::to_string(n->second) + " of its records, as " + Describe(f) +
                        ": ignored");
        return;
      }
      Note("the FMT record " + AtByte(pos) + " redefines " + Describe(o) +
           ", which has no records yet, as " + Describe(f));
      const auto m = out_.messages.find(o.name);
      if (m != out_.messages.end() && m->second.type == type && m->second.offsets.empty())
        out_.messages.erase(m);
    }
    AddFormat(std::move(f));
  }

  void AddFormat(MessageFormat f) {
    const std::uint8_t type = f.type;
    if (!f.decodable())
      Note("message " + Describe(f) + " cannot be decoded: " + f.undecodable +
           "; its records are framed and counted");
    role_[type] = f.name == "FMTU"   ? RecordRole::kFmtu
                  : f.name == "UNIT" ? RecordRole::kUnit
                  : f.name == "MULT" ? RecordRole::kMult
                                     : RecordRole::kData;
    kept_[type] = nullptr;
    if (f.name.empty()) {
      Note("the FMT record " + AtByte(f.defined_at) + " gives type " + std::to_string(type) +
           " no name: its records are counted, not kept");
    } else {
      const auto [it, added] = out_.messages.try_emplace(f.name);
      if (added) it->second.type = type;
      if (it->second.type == type)
        kept_[type] = &it->second;
      else
        Damage(f.defined_at, "the FMT record " + AtByte(f.defined_at) + " names type " +
                                 std::to_string(type) + " '" + f.name + "', the name of type " +
                                 std::to_string(it->second.type) +
                                 ": its records are counted, not kept");
    }
    out_.formats[type] = std::move(f);
  }

  void FmtuRecord(const MessageFormat& f, const std::uint8_t* payload) {
    const auto t = f.IndexOf("FmtType"), u = f.IndexOf("UnitIds"), m = f.IndexOf("MultIds");
    const std::optional<std::uint8_t> type =
        t ? ByteValue(payload, f.fields[*t]) : std::optional<std::uint8_t>();
    if (!type || !u || !m || KindOf(f.fields[*u]) != FieldKind::kText ||
        KindOf(f.fields[*m]) != FieldKind::kText)
      return NoteUnreadable(RecordRole::kFmtu, "FMTU", "FmtType, UnitIds and MultIds");
    out_.units[*type] =
        MessageUnits{FieldText(payload, f.fields[*u]), FieldText(payload, f.fields[*m])};
  }

  void UnitRecord(const MessageFormat& f, const std::uint8_t* payload) {
    const auto i = f.IndexOf("Id"), l = f.IndexOf("Label");
    const std::optional<std::uint8_t> id =
        i ? ByteValue(payload, f.fields[*i]) : std::optional<std::uint8_t>();
    if (!id || !l || KindOf(f.fields[*l]) != FieldKind::kText)
      return NoteUnreadable(RecordRole::kUnit, "UNIT", "Id and Label");
    out_.unit_labels[static_cast<char>(*id)] = FieldText(payload, f.fields[*l]);
  }

  void MultRecord(const MessageFormat& f, const std::uint8_t* payload) {
    const auto i = f.IndexOf("Id"), v = f.IndexOf("Mult");
    const std::optional<std::uint8_t> id =
        i ? ByteValue(payload, f.fields[*i]) : std::optional<std::uint8_t>();
    if (!id || !v || KindOf(f.fields[*v]) != FieldKind::kFloat)
      return NoteUnreadable(RecordRole::kMult, "MULT", "Id and Mult");
    out_.multipliers[static_cast<char>(*id)] = RawValue(payload, f.fields[*v]);
  }

  void NoteUnreadable(RecordRole role, const char* name, const char* fields) {
    bool& noted = unreadable_noted_[static_cast<std::size_t>(role)];
    if (noted) return;
    noted = true;
    Note(std::string(name) + " records without the fields " + fields +
         " (or not decodable): the units they give are not read");
  }

  void Damage(std::size_t offset, std::string what) {
    ++out_.damage_count;
    if (!out_.problem.empty()) return;
    out_.problem = std::move(what);
    out_.problem_offset = offset;
  }

  void Note(std::string what) {
    if (out_.notes.size() < kMaxNotes)
      out_.notes.push_back(std::move(what));
    else if (out_.notes.size() == kMaxNotes)
      out_.notes.push_back("further notes are left out");
  }

  DataflashFile& out_;
  const std::uint8_t* data_;
  std::size_t size_;
  std::array<RecordRole, 256> role_{};
  // Where each type's records go; nullptr for a type without a name of its own.
  std::array<MessageRecords*, 256> kept_{};
  std::array<bool, 4> unreadable_noted_{};
};

[[noreturn]] void ThrowTooLarge(const std::string& source, std::uint64_t size) {
  throw DataflashError(source + ": " + std::to_string(size) + " bytes, more than the " +
                       std::to_string(kMaxFileBytes) + " bytes this reader takes");
}

DataflashFile ParseOwned(std::string bytes, const std::string& source) {
  if (bytes.empty()) throw DataflashError(source + ": empty, not a DataFlash log");
  if (bytes.size() > kMaxFileBytes) ThrowTooLarge(source, bytes.size());
  if (!LooksLikeDataflash(bytes))
    throw DataflashError(source +
                         ": not an ArduPilot DataFlash log (it does not start with an FMT "
                         "record, bytes A3 95 80)");
  DataflashFile f;
  f.source = source;
  f.file_size = bytes.size();
  f.bytes = std::move(bytes);
  RecordWalk(f).Run();
  return f;
}

}  // namespace

const MessageFormat* DataflashFile::FindFormat(std::string_view name) const {
  const MessageRecords* m = FindMessage(name);
  if (!m) return nullptr;
  const auto it = formats.find(m->type);
  return it == formats.end() ? nullptr : &it->second;
}

const MessageRecords* DataflashFile::FindMessage(std::string_view name) const {
  const auto it = messages.find(std::string(name));
  return it == messages.end() ? nullptr : &it->second;
}

std::size_t DataflashFile::RecordCount(std::string_view name) const {
  const MessageRecords* m = FindMessage(name);
  return m ? m->size() : 0;
}

std::string DataflashFile::UnitOf(const MessageFormat& format, std::size_t field) const {
  const auto it = units.find(format.type);
  if (it == units.end() || field >= it->second.unit_ids.size()) return "";
  const char id = it->second.unit_ids[field];
  if (id == '-' || id == '#') return "";
  const auto label = unit_labels.find(id);
  return label == unit_labels.end() ? "" : label->second;
}

std::optional<double> DataflashFile::MultiplierOf(const MessageFormat& format,
                                                  std::size_t field) const {
  const auto it = units.find(format.type);
  if (it == units.end() || field >= it->second.mult_ids.size()) return std::nullopt;
  const char id = it->second.mult_ids[field];
  if (id == '-') return std::nullopt;
  const auto m = multipliers.find(id);
  if (m == multipliers.end() || !std::isfinite(m->second) || m->second == 0.0) return std::nullopt;
  return m->second;
}

std::optional<std::size_t> DataflashFile::InstanceField(const MessageFormat& format) const {
  const auto it = units.find(format.type);
  if (it == units.end()) return std::nullopt;
  const std::string& ids = it->second.unit_ids;
  for (std::size_t i = 0; i < ids.size() && i < format.fields.size(); ++i) {
    const char type = format.fields[i].type;
    if (ids[i] == '#' && (type == 'B' || type == 'M')) return i;
  }
  return std::nullopt;
}

bool LooksLikeDataflash(std::string_view head) {
  return head.size() >= kRecordHeaderSize && static_cast<std::uint8_t>(head[0]) == kRecordHead1 &&
         static_cast<std::uint8_t>(head[1]) == kRecordHead2 &&
         static_cast<std::uint8_t>(head[2]) == kFmtType;
}

DataflashFile Parse(std::string_view bytes, const std::string& source) {
  if (bytes.size() > kMaxFileBytes) ThrowTooLarge(source, bytes.size());  // before the copy
  return ParseOwned(std::string(bytes), source);
}

DataflashFile Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw DataflashError(path + ": cannot open file (" + std::strerror(errno) + ")");
  const std::streamoff size = in.tellg();
  if (size < 0) throw DataflashError(path + ": cannot tell the file's size");
  if (static_cast<std::uint64_t>(size) > kMaxFileBytes)
    ThrowTooLarge(path, static_cast<std::uint64_t>(size));
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (size > 0 && !in.read(bytes.data(), size)) throw DataflashError(path + ": cannot read file");
  return ParseOwned(std::move(bytes), path);
}

}  // namespace odonata::dataflash
