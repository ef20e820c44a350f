#pragma once
// A PX4 ULog flight log read into memory (PX4's "ULog File Format"): the header, the definitions
// (flag bits, formats, information, parameters) and every message of the data section, the data
// samples kept as their raw bytes so that any field reads back exactly.
//
// A damaged file is read up to the damage: parsing stops at the first message that cannot be
// read, `problem` says where and why, and everything before it stays available. A log the
// autopilot cut mid-message (power loss) ends that way too. Only a file that is no ULog at all
// (or unreadable) throws, and the strict entry points throw for any problem.

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ulog/ulog_format.hpp"
#include "ulog/ulog_value.hpp"

namespace odonata::ulog {

/// The 'B' message (file format version 1 onwards), right after the header.
struct FlagBits {
  bool present = false;
  std::array<std::uint8_t, 8> compat{};
  std::array<std::uint8_t, 8> incompat{};
  /// Where data appended after the log was first closed starts (0: unused).
  std::array<std::uint64_t, 3> appended_offsets{};
  bool has_default_parameters() const { return (compat[0] & 1u) != 0; }
  bool has_appended_data() const { return (incompat[0] & 1u) != 0; }
};

/// One 'A' message and the data ('D') messages logged under its msg_id.
struct Subscription {
  std::uint16_t msg_id = 0;
  std::uint8_t multi_id = 0;        ///< instance of a topic logged several times (0: the first)
  std::string topic;                ///< the format's name
  std::uint64_t subscribed_at = 0;  ///< byte offset of the 'A' message
  std::shared_ptr<const Layout> layout;
  std::vector<std::uint64_t> timestamps_us;  ///< each sample's "timestamp" field, in file order
  /// Sample i's data bytes (without msg_id) at [i * layout->logged_size, (i + 1) * …): the
  /// trailing padding a data message may carry is dropped.
  std::vector<std::uint8_t> data;
  /// Index of the first sample read from appended data (== size() when there is none).
  std::size_t first_appended_sample = 0;
  bool removed = false;  ///< an 'R' message unsubscribed it

  std::size_t size() const { return timestamps_us.size(); }
  const std::uint8_t* Sample(std::size_t i) const { return data.data() + i * layout->logged_size; }
  /// Element `element` of `field` in sample `i` as a double.
  double Value(std::size_t i, const FieldLayout& field, std::size_t element = 0) const {
    return ReadAsDouble(Sample(i) + field.offset + element * SizeOf(field.type), field.type);
  }
};

struct ParameterChange {
  /// Parameter messages carry no time: that of the latest data sample before it (the header's
  /// start time before any), as PX4's own reader dates them.
  std::uint64_t time_us = 0;
  std::string name;
  TypedValue value;
};

/// A 'Q' message: a default value, for the groups set in `default_types` (bit 0: system-wide,
/// bit 1: the current configuration).
struct DefaultParameter {
  std::uint8_t default_types = 0;
  std::string name;
  TypedValue value;
};

/// An 'L' (printf output) or 'C' (tagged) message.
struct LogMessage {
  std::uint8_t level = 0;            ///< '0' (emergency) … '7' (debug), as the kernel's
  std::optional<std::uint16_t> tag;  ///< set for 'C' messages
  std::uint64_t timestamp_us = 0;
  std::string text;
};

/// An 'O' message: logging lost messages for `duration_ms`, dated like a parameter change.
struct Dropout {
  std::uint64_t time_us = 0;
  std::uint16_t duration_ms = 0;
};

struct UlogFile {
  std::string source;  ///< the path or name it was read from
  std::size_t file_size = 0;
  std::uint8_t version = 0;  ///< the header's file format version (0 and 1 known; others read)
  std::uint64_t start_time_us = 0;
  FlagBits flags;

  std::map<std::string, Format> formats;
  std::vector<Subscription> subscriptions;  ///< in the order of their 'A' messages

  std::map<std::string, TypedValue> info;  ///< 'I' messages (a repeated key keeps the last)
  /// 'M' messages per key, in file order; a message with is_continued set is appended to the
  /// previous value of its key.
  std::map<std::string, std::vector<TypedValue>> multi_info;
  std::map<std::string, TypedValue> initial_parameters;  ///< 'P' before the data section
  std::vector<ParameterChange> changed_parameters;       ///< 'P' in the data section
  std::vector<DefaultParameter> default_parameters;      ///< 'Q', in file order
  std::vector<LogMessage> log_messages;                  ///< 'L' and 'C', in file order
  std::size_t sync_count = 0;                            ///< 'S'
  std::vector<Dropout> dropouts;                         ///< 'O'
  std::uint64_t dropout_total_ms = 0;

  std::map<char, std::size_t> message_counts;          ///< every message read, by type
  std::map<char, std::size_t> unknown_message_counts;  ///< those of types this reader skips
  /// Messages read from appended data (after the first appended offset).
  std::size_t appended_messages = 0;
  /// What was odd but readable: a future file version, unknown compatible flags, the bytes of a
  /// cut message skipped before appended data, zero padding at the end.
  std::vector<std::string> notes;

  /// Empty when the whole file was read; else the first damage, e.g. "message of type 'D' at
  /// byte 123456 claims 900 bytes, only 12 left". Everything before it was read.
  std::string problem;
  std::uint64_t problem_offset = 0;  ///< byte offset of that damage
  bool complete() const { return problem.empty(); }

  /// The subscription of `msg_id`, or nullptr.
  const Subscription* FindSubscription(std::uint16_t msg_id) const;
  /// The first subscription of `topic` instance `multi_id`, or nullptr.
  const Subscription* FindTopic(std::string_view topic, std::uint8_t multi_id = 0) const;
  std::size_t MessageCount(char type) const;
};

/// Reads the ULog file at `path`.
/// @throws UlogError if it cannot be read, is shorter than the 16-byte header, or does not start
///   with the ULog magic. Damage after the header is reported in `problem`, not thrown.
UlogFile Read(const std::string& path);
/// Parses ULog bytes; `source_name` names them in messages. Throws like Read.
UlogFile Parse(std::string_view bytes, const std::string& source_name);
UlogFile Parse(const std::vector<std::uint8_t>& bytes, const std::string& source_name);

/// As Read and Parse, but any damage throws UlogError ("<source>: <problem>").
UlogFile ReadStrict(const std::string& path);
UlogFile ParseStrict(std::string_view bytes, const std::string& source_name);

}  // namespace odonata::ulog
