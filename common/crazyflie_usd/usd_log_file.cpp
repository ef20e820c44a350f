#include "crazyflie_usd/usd_log_file.hpp"

#include "crazyflie_usd/byte_cursor.hpp"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>
#include <unordered_map>
#include <utility>

namespace odonata::crazyflie_usd {
namespace {

constexpr unsigned char kMagic = 0xBC;
constexpr std::size_t kStartSize = 5;  // magic, version, event type count
constexpr std::size_t kCrcSize = 4;

std::string Hex(std::uint64_t v, int digits) {
  char s[24];
  std::snprintf(s, sizeof s, "0x%0*llx", digits, static_cast<unsigned long long>(v));
  return s;
}

std::string IdLabel(std::uint16_t id) {
  return id == kFixedFrequencyId ? Hex(id, 4) : std::to_string(id);
}

std::string CodeLabel(char code) {
  const auto c = static_cast<unsigned char>(code);
  if (c > 0x20 && c < 0x7f) return std::string("'") + code + "'";
  return Hex(c, 2);
}

std::uint16_t U16At(std::string_view bytes, std::size_t at) {
  return static_cast<std::uint16_t>(
      ReadUnsignedLE(reinterpret_cast<const unsigned char*>(bytes.data()) + at, 2));
}

// Why `bytes` is no micro-SD log this reader takes, or "" when it is one: the one test behind
// both LooksLikeUsdLog and Parse, so that they never disagree.
std::string NotALog(std::string_view bytes) {
  if (bytes.empty()) return "empty, not a Crazyflie micro-SD log";
  const auto first = static_cast<unsigned char>(bytes[0]);
  if (first != kMagic)
    return "not a Crazyflie micro-SD log (it starts with " + Hex(first, 2) + ", not 0xbc)";
  if (bytes.size() < kStartSize)
    return "only " + std::to_string(bytes.size()) +
           " bytes, fewer than the 5 a micro-SD log starts with (0xbc, u16 version, u16 event "
           "type count)";
  const std::uint16_t version = U16At(bytes, 1);
  if (version != 1 && version != 2)
    return "version " + std::to_string(version) +
           " of the micro-SD log format: this reader knows versions 1 and 2 (not a micro-SD "
           "log, or a newer firmware's)";
  const std::uint16_t types = U16At(bytes, 3);
  if (static_cast<std::size_t>(types) > kMaxEventTypes)
    return "declares " + std::to_string(types) +
           " event types; the firmware writes a few, this reader refuses more than " +
           std::to_string(kMaxEventTypes) + " (not a micro-SD log, or damaged)";
  return "";
}

// Value of struct code `code` at `p`; `code` is one a declaration passed (SizeOfCode > 0).
double DecodeValue(const unsigned char* p, char code) {
  switch (code) {
    case 'B':
      return p[0];
    case 'b':
      return static_cast<std::int8_t>(p[0]);
    case 'H':
      return static_cast<double>(ReadUnsignedLE(p, 2));
    case 'h':
      return static_cast<std::int16_t>(static_cast<std::uint16_t>(ReadUnsignedLE(p, 2)));
    case 'I':
      return static_cast<double>(ReadUnsignedLE(p, 4));
    case 'i':
      return static_cast<std::int32_t>(static_cast<std::uint32_t>(ReadUnsignedLE(p, 4)));
    case 'f': {
      const auto bits = static_cast<std::uint32_t>(ReadUnsignedLE(p, 4));
      float v;
      std::memcpy(&v, &bits, sizeof v);
      return v;
    }
    default:  // 'e'
      return HalfToDouble(static_cast<std::uint16_t>(ReadUnsignedLE(p, 2)));
  }
}

// One pass over the file, in order: the event type declarations, the records, the trailer.
class LogWalk {
 public:
  LogWalk(std::string_view bytes, UsdLogFile& out) : bytes_(bytes), out_(out) {}

  void Run() {
    if (!Header()) return;
    const std::size_t after = bytes_.size() - out_.header_size;
    if (after < kCrcSize) {
      Fail(out_.header_size, "the header ends at byte " + std::to_string(out_.header_size) +
                                 " and the file " + std::to_string(after) +
                                 " bytes later, without room for the 4-byte CRC trailer: it "
                                 "was cut, and holds no record");
      return;
    }
    const std::size_t end = bytes_.size() - kCrcSize;
    std::size_t pos = out_.header_size;
    while (pos < end && Record(pos, end)) {
    }
    Trailer(end);
  }

 private:
  // The event type declarations; false (and the problem said) when they cannot all be read.
  bool Header() {
    const std::size_t types = U16At(bytes_, 3);
    ByteCursor in(bytes_, kStartSize);
    try {
      for (std::size_t k = 0; k < types; ++k) Declaration(in);
    } catch (const CursorDamage& d) {
      Fail(d.offset, d.what + "; " + std::to_string(out_.event_types.size()) + " of the " +
                         std::to_string(types) +
                         " event types were declared before it, and no record is read");
      return false;
    }
    out_.header_size = in.at();
    return true;
  }

  // u16 id, NUL-terminated name, u16 variable count, the variables. A declaration that cannot be
  // read whole stops the walk: no record is read after it, so the index may keep its id.
  void Declaration(ByteCursor& in) {
    EventType t;
    const std::size_t at = in.at();
    t.declared_at = at;
    t.id = in.U16("an event type's id");
    t.name = std::string(in.CString("an event type's name", kMaxNameLength));
    if (t.name.empty())
      throw CursorDamage{at, "event type " + IdLabel(t.id) + " declared at byte " +
                                 std::to_string(at) + " has no name"};
    const std::string label = "event type '" + Printable(t.name) + "' (id " + IdLabel(t.id) + ")";
    const auto [first, added] = index_.emplace(t.id, out_.event_types.size());
    if (!added) {
      const EventType& old = out_.event_types[first->second];
      throw CursorDamage{at, label + " at byte " + std::to_string(at) +
                                 " takes an id already declared by '" + Printable(old.name) +
                                 "' at byte " + std::to_string(old.declared_at)};
    }
    const std::size_t count_at = in.at();
    const std::size_t count = in.U16("the variable count of " + label);
    if (count > kMaxVariablesPerType)
      throw CursorDamage{count_at, label + " declares " + std::to_string(count) +
                                       " variables at byte " + std::to_string(count_at) +
                                       "; the firmware logs some 70 at most, this reader "
                                       "refuses more than " +
                                       std::to_string(kMaxVariablesPerType)};
    for (std::size_t j = 0; j < count; ++j) VariableDeclaration(in, t, label);
    out_.event_types.push_back(std::move(t));
  }

  // "name(T)", NUL-terminated.
  void VariableDeclaration(ByteCursor& in, EventType& t, const std::string& label) {
    const std::size_t at = in.at();
    const std::string ordinal =
        "variable " + std::to_string(t.variables.size() + 1) + " of " + label;
    const std::string_view decl = in.CString(ordinal, kMaxNameLength + 3);
    if (decl.size() < 4 || decl[decl.size() - 3] != '(' || decl.back() != ')')
      throw CursorDamage{at, ordinal + " at byte " + std::to_string(at) + " is '" +
                                 Printable(decl) + "', not 'name(T)'"};
    const char code = decl[decl.size() - 2];
    const std::string_view name = decl.substr(0, decl.size() - 3);
    if (SizeOfCode(code) == 0)
      throw CursorDamage{at, ordinal + " at byte " + std::to_string(at) + ", '" + Printable(name) +
                                 "', has type code " + CodeLabel(code) +
                                 "; the format's codes are B b H h I i f e"};
    t.variables.push_back(Variable{std::string(name), code});
    t.record_size += SizeOfCode(code);
  }

  // The record at `pos` (u16 id, timestamp, values), `end` being where the trailer starts;
  // advances past it, or says the problem and returns false.
  bool Record(std::size_t& pos, std::size_t end) {
    const std::size_t head = out_.version == 1 ? 2 + 4 : 2 + 8;
    const std::size_t left = end - pos;
    const auto* at = reinterpret_cast<const unsigned char*>(bytes_.data()) + pos;
    if (left < 2)
      return Fail(pos, "the record at byte " + std::to_string(pos) +
                           " is cut: 1 byte is left before the CRC trailer at byte " +
                           std::to_string(end) + Cut() + Unread(pos, end));
    const auto id = static_cast<std::uint16_t>(ReadUnsignedLE(at, 2));
    const auto it = index_.find(id);
    if (it == index_.end())
      return Fail(pos, "the record at byte " + std::to_string(pos) + " has type id " + IdLabel(id) +
                           " (" + Hex(id, 4) +
                           "), which the header does not declare: its size is unknown" +
                           Unread(pos, end));
    EventType& t = out_.event_types[it->second];
    const std::size_t size = head + t.record_size;
    if (left < size)
      return Fail(pos, "the record of '" + Printable(t.name) + "' (id " + IdLabel(id) +
                           ") at byte " + std::to_string(pos) + " is cut: it needs " +
                           std::to_string(size) + " bytes, " + std::to_string(left) +
                           " are left before the CRC trailer at byte " + std::to_string(end) +
                           Cut() + Unread(pos, end));
    const std::uint64_t stamp = ReadUnsignedLE(at + 2, head - 2);
    t.time_us.push_back(out_.version == 1 ? stamp * 1000 : stamp);
    const unsigned char* value = at + head;
    for (const Variable& v : t.variables) {
      t.values.push_back(DecodeValue(value, v.code));
      value += SizeOfCode(v.code);
    }
    ++out_.records;
    pos += size;
    return true;
  }

  // The last 4 bytes: the CRC32 of all before them.
  void Trailer(std::size_t end) {
    out_.crc_stored = static_cast<std::uint32_t>(
        ReadUnsignedLE(reinterpret_cast<const unsigned char*>(bytes_.data()) + end, 4));
    out_.crc_computed = Crc32(bytes_.substr(0, end));
    out_.crc_valid = out_.crc_stored == out_.crc_computed;
    if (out_.crc_valid) return;
    out_.notes.push_back(
        "the CRC32 trailer at byte " + std::to_string(end) + " is " + Hex(out_.crc_stored, 8) +
        " but the bytes before it give " + Hex(out_.crc_computed, 8) +
        (out_.complete() ? ": bytes changed after the Crazyflie wrote them; the records are read "
                           "as they are"
                         : ": the file is not as the Crazyflie wrote it (see the problem)"));
  }

  static std::string Cut() { return " (the log was cut, as by a power loss, or a byte changed)"; }

  std::string Unread(std::size_t pos, std::size_t end) const {
    return "; the " + std::to_string(end - pos) + " bytes from byte " + std::to_string(pos) +
           " to the trailer are not read (" + std::to_string(out_.records) +
           " records before them are)";
  }

  bool Fail(std::size_t offset, std::string what) {
    out_.problem = std::move(what);
    out_.problem_offset = offset;
    return false;
  }

  std::string_view bytes_;
  UsdLogFile& out_;
  std::unordered_map<std::uint16_t, std::size_t> index_;  // id -> event_types index
};

}  // namespace

std::size_t SizeOfCode(char code) {
  switch (code) {
    case 'B':
    case 'b':
      return 1;
    case 'H':
    case 'h':
    case 'e':
      return 2;
    case 'I':
    case 'i':
    case 'f':
      return 4;
    default:
      return 0;
  }
}

std::string TypeName(char code) {
  switch (code) {
    case 'B':
      return "uint8_t";
    case 'b':
      return "int8_t";
    case 'H':
      return "uint16_t";
    case 'h':
      return "int16_t";
    case 'I':
      return "uint32_t";
    case 'i':
      return "int32_t";
    case 'f':
      return "float";
    case 'e':
      return "half";
    default:
      return "";
  }
}

double HalfToDouble(std::uint16_t bits) {
  const bool negative = (bits & 0x8000u) != 0;
  const int exponent = (bits >> 10) & 0x1f;
  const int fraction = bits & 0x3ff;
  double v;
  if (exponent == 0)
    v = std::ldexp(fraction, -24);  // zero and subnormals: fraction × 2^-24
  else if (exponent == 31)
    v = fraction == 0 ? std::numeric_limits<double>::infinity()
                      : std::numeric_limits<double>::quiet_NaN();
  else
    v = std::ldexp(fraction + 1024, exponent - 25);  // (1 + fraction / 2^10) × 2^(exponent - 15)
  return negative ? -v : v;
}

std::uint32_t Crc32(std::string_view bytes) {
  static const std::array<std::uint32_t, 256> kTable = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const char ch : bytes)
    crc = kTable[(crc ^ static_cast<unsigned char>(ch)) & 0xffu] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

const EventType* UsdLogFile::FindType(std::uint16_t id) const {
  for (const auto& t : event_types)
    if (t.id == id) return &t;
  return nullptr;
}

const EventType* UsdLogFile::FindType(std::string_view name) const {
  for (const auto& t : event_types)
    if (t.name == name) return &t;
  return nullptr;
}

std::size_t UsdLogFile::RecordCount(std::uint16_t id) const {
  const EventType* t = FindType(id);
  return t ? t->size() : 0;
}

bool LooksLikeUsdLog(std::string_view head) { return NotALog(head).empty(); }

UsdLogFile Parse(std::string_view bytes, const std::string& source) {
  if (const std::string why = NotALog(bytes); !why.empty()) throw UsdLogError(source + ": " + why);
  UsdLogFile f;
  f.source = source;
  f.file_size = bytes.size();
  f.version = U16At(bytes, 1);
  LogWalk(bytes, f).Run();
  return f;
}

UsdLogFile Read(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw UsdLogError(path + ": a directory, not a micro-SD log");
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw UsdLogError(path + ": cannot open file (" + std::strerror(errno) + ")");
  const std::streamoff size = in.tellg();
  if (size < 0) throw UsdLogError(path + ": cannot tell the file's size");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), size)) throw UsdLogError(path + ": cannot read file");
  return Parse(bytes, path);
}

}  // namespace odonata::crazyflie_usd
