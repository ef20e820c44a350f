#pragma once
// A Crazyflie micro-SD deck log (what the Flapper Drone writes: log00, log01, …) read into memory,
// as the firmware's usddeck.c writes it, little-endian:
//   0xBC; u16 version (1 or 2); u16 number of event types;
//   per event type: u16 id (0xFFFF: the fixed-frequency block), its NUL-terminated name, u16
//     variable count, each variable a NUL-terminated "name(T)": "group.name(T)" for a log
//     variable, a bare "name(T)" for a field of the event's own payload; T a struct code
//     (B b H h I i f, e an IEEE half float);
//   records: u16 type id, the timestamp (version 2: u64 µs; version 1: u32 ms), the values
//     packed in the declared order, without padding;
//   u32 CRC32 (zlib's) of every byte before it.
//
// A damaged file is read up to the damage: the walk stops at the first declaration or record that
// cannot be read (a record of an undeclared type id, whose size is then unknown; a record cut
// short; a header cut short or declaring what this reader refuses), `problem` says where and why
// and what was not read, and everything before it stays available. A log the Crazyflie cut (a
// power loss: no CRC trailer) ends that way too. A CRC that does not match the bytes is said in
// `notes` and `crc_valid`, and the records are still read as they are. Only what is no such log
// (or cannot be read) throws.
//
// Memory: about 8 bytes per value and per record read, at most some 9 times the file's size.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace odonata::crazyflie_usd {

class UsdLogError : public std::runtime_error {
 public:
  explicit UsdLogError(const std::string& what) : std::runtime_error(what) {}
};

inline constexpr std::uint16_t kFixedFrequencyId = 0xFFFF;
/// Declarations refused beyond these (the firmware writes a few event types of at most some 70
/// variables each): a header that claims more is not a log, or is damaged.
inline constexpr std::size_t kMaxEventTypes = 1024;
inline constexpr std::size_t kMaxVariablesPerType = 1024;
inline constexpr std::size_t kMaxNameLength = 255;

/// Bytes of a value of struct code `code` (B b H h I i f e), 0 for any other code.
std::size_t SizeOfCode(char code);
/// The C type of struct code `code`: "uint8_t", "int16_t", "float", "half" (e), … ("" if none).
std::string TypeName(char code);
/// The IEEE 754 binary16 value with bits `bits` (subnormals, ±inf and NaN included).
double HalfToDouble(std::uint16_t bits);
/// zlib's CRC32 (polynomial 0xEDB88320, reflected, initial and final XOR 0xFFFFFFFF).
std::uint32_t Crc32(std::string_view bytes);

struct Variable {
  std::string name;  ///< as declared, without "(T)": "gyro.x", or a payload field "distanceDiff"
  char code = 'f';   ///< struct code: B b H h I i f e
};

/// One declared event type and the records logged under its id.
struct EventType {
  std::uint16_t id = 0;
  std::string name;  ///< "estGyroscope", "fixedFrequency", …
  std::vector<Variable> variables;
  std::size_t record_size = 0;    ///< bytes of values per record (without id and timestamp)
  std::uint64_t declared_at = 0;  ///< byte offset of its declaration
  /// Per record, in file order: the Crazyflie's clock in µs since it started (version 1 logs it
  /// in ms: ms × 1000).
  std::vector<std::uint64_t> time_us;
  /// Record i's variable j at values[i * variables.size() + j], as double (exact for every code).
  std::vector<double> values;

  std::size_t size() const { return time_us.size(); }
  double Value(std::size_t record, std::size_t variable) const {
    return values[record * variables.size() + variable];
  }
  bool fixed_frequency() const { return id == kFixedFrequencyId; }
};

struct UsdLogFile {
  std::string source;  ///< the path or name it was read from
  std::size_t file_size = 0;
  std::uint16_t version = 0;           ///< 1 (ms timestamps) or 2 (µs timestamps)
  std::vector<EventType> event_types;  ///< in the header's order, each read whole
  std::size_t header_size = 0;         ///< where the records start (0: the header is damaged)
  std::size_t records = 0;             ///< records read, of every type

  /// The CRC32 trailer matches the bytes before it. Checked when the header was read whole and
  /// at least 4 bytes follow it; false otherwise.
  bool crc_valid = false;
  std::uint32_t crc_stored = 0;    ///< the trailer (the file's last 4 bytes)
  std::uint32_t crc_computed = 0;  ///< over every byte before them
  /// What was odd but readable (a CRC mismatch: the records are read as they are).
  std::vector<std::string> notes;

  /// Empty when every record up to the trailer was read; else the first damage, e.g. "record of
  /// 'estGyroscope' (id 3) at byte 1234 is cut: …", with what was not read.
  std::string problem;
  std::uint64_t problem_offset = 0;  ///< byte offset of that damage
  bool complete() const { return problem.empty(); }
  /// Read whole and as written: complete, and the CRC matches.
  bool intact() const { return complete() && crc_valid; }

  /// The event type of id `id` / named `name`, or nullptr.
  const EventType* FindType(std::uint16_t id) const;
  const EventType* FindType(std::string_view name) const;
  /// Records read of type `id` (0 for an undeclared id).
  std::size_t RecordCount(std::uint16_t id) const;
};

/// Whether `head` (the first bytes of a file, 5 or more) starts a micro-SD log: 0xBC, version 1 or
/// 2, at most kMaxEventTypes event types. By content only, never by file name: exactly the
/// files Parse accepts.
bool LooksLikeUsdLog(std::string_view head);

/// Parses micro-SD log bytes; `source` names them in messages.
/// @throws UsdLogError for what is no such log: empty, not starting with 0xBC, shorter than the
///   5 bytes of magic, version and type count, another version than 1 or 2, more than
///   kMaxEventTypes event types. Damage after those 5 bytes is reported in `problem`.
UsdLogFile Parse(std::string_view bytes, const std::string& source);

/// Reads the micro-SD log at `path`.
/// @throws UsdLogError if it cannot be opened or read, or as Parse.
UsdLogFile Read(const std::string& path);

}  // namespace odonata::crazyflie_usd
