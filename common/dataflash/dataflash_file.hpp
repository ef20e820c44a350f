#pragma once
// An ArduPilot DataFlash log (.bin) read into memory: the FMT records that lay out each message
// type, the records of every message (kept in place, by byte offset), and the units FMTU, UNIT and
// MULT records give.
//
// Damage does not stop the reading: a record of a type no FMT describes, bytes between records
// that are no record (the walk resumes at the next 0xA3 0x95, counting the bytes it skipped) and a
// last record cut by the end of the file (power lost while logging) are each reported, the first
// of them in `problem` with its byte offset; every whole record of a known type is read. Only
// bytes that are no DataFlash log at all (or a file that cannot be read) throw.
//
// Memory: the file's bytes and 8 bytes per record (about 1.2 times the file for ArduPilot's
// records of some 40 bytes); files over kMaxFileBytes are refused.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dataflash/dataflash_format.hpp"

namespace odonata::dataflash {

/// The largest file Read and Parse take (2 GiB).
inline constexpr std::size_t kMaxFileBytes = std::size_t{1} << 31;

/// An FMTU record: one unit id and one multiplier id per field of its message, in field order.
/// Unit ids name UNIT records ('-': no unit, '#': the field is the message's instance number);
/// multiplier ids name MULT records ('-': none, '?': not known).
struct MessageUnits {
  std::string unit_ids;
  std::string mult_ids;
};

/// The records of one message type, in file order.
struct MessageRecords {
  std::uint8_t type = 0;
  std::vector<std::uint64_t> offsets;  ///< byte offset of each record (of its 0xA3)
  std::size_t size() const { return offsets.size(); }
};

struct DataflashFile {
  std::string source;  ///< the path or name it was read from
  std::size_t file_size = 0;
  std::string bytes;  ///< the whole file: records are read in place

  /// Every FMT read, by type (FMT itself, type 128, built in).
  std::map<std::uint8_t, MessageFormat> formats;
  /// Every message an FMT names, by name, with or without records.
  std::map<std::string, MessageRecords> messages;
  std::map<std::uint8_t, MessageUnits> units;  ///< FMTU records, by the type they describe
  std::map<char, std::string> unit_labels;     ///< UNIT records: id → "deg", "rad/s", …
  std::map<char, double> multipliers;          ///< MULT records: id → 0.01, 1e-7, …

  std::map<std::uint8_t, std::size_t> record_counts;        ///< records read, by type
  std::map<std::uint8_t, std::size_t> unknown_type_counts;  ///< headers of types without FMT
  /// Bytes read as no record: between records (resynchronised), of types without FMT, and a cut
  /// last record. Zero or 0xFF padding at the end is not counted (see notes).
  std::size_t bytes_skipped = 0;
  std::size_t damage_count = 0;  ///< places where bytes were skipped or an FMT was refused
  /// What was odd but readable: records that cannot be decoded, padding at the end, FMTU, UNIT or
  /// MULT records without the fields they should have.
  std::vector<std::string> notes;

  /// Empty when every byte was read as a record; else the first damage, e.g. "the last record,
  /// 'AHR2' (type 141, 45 bytes) at byte 65512, is cut: only 24 bytes are left".
  std::string problem;
  std::uint64_t problem_offset = 0;  ///< byte offset of that damage
  bool complete() const { return problem.empty(); }

  /// The format of the message called `name`, or nullptr.
  const MessageFormat* FindFormat(std::string_view name) const;
  /// The records of the message called `name`, or nullptr.
  const MessageRecords* FindMessage(std::string_view name) const;
  /// Records read of the message called `name` (0 for an unknown name).
  std::size_t RecordCount(std::string_view name) const;
  /// The payload (after the 3-byte header) of the record at `record_offset`.
  /// @pre record_offset is one of a MessageRecords' offsets.
  const std::uint8_t* Payload(std::uint64_t record_offset) const {
    return reinterpret_cast<const std::uint8_t*>(bytes.data()) + record_offset + kRecordHeaderSize;
  }

  /// The unit FMTU and UNIT give field `field` of `format` ("deg"); "" when they give none.
  std::string UnitOf(const MessageFormat& format, std::size_t field) const;
  /// The multiplier FMTU and MULT give field `field` of `format`: the logged number times it is
  /// in the unit. nullopt when they give none ('-', an id without MULT, 0 or not finite).
  std::optional<double> MultiplierOf(const MessageFormat& format, std::size_t field) const;
  /// The field FMTU marks as the instance number ('#'): the first such uint8 field (B or M, as
  /// ArduPilot logs its instances), or nullopt.
  std::optional<std::size_t> InstanceField(const MessageFormat& format) const;
};

/// Whether `head` (the first bytes of a file, 3 or more) starts a DataFlash log: a record header
/// 0xA3 0x95 of type 128, the FMT record every log opens with. Content, not the file's name.
bool LooksLikeDataflash(std::string_view head);

/// Parses DataFlash bytes; `source` names them in messages. Damage is reported in `problem`.
/// @throws DataflashError for empty bytes, bytes that do not start like a DataFlash log, or more
///   than kMaxFileBytes.
DataflashFile Parse(std::string_view bytes, const std::string& source);

/// Reads the DataFlash log at `path`.
/// @throws DataflashError if it cannot be opened or read, or as Parse.
DataflashFile Read(const std::string& path);

}  // namespace odonata::dataflash
