#pragma once
// A small DataFlash writer for the tests: builds logs record by record as ArduPilot's logger lays
// them out (0xA3 0x95, the type, the fields little-endian as the type's FMT says), and damaged
// ones too (bytes outside any record, records of types without FMT, FMTs of any length). The fuzz
// harness's seed files (tests/fuzz/corpus/dataflash_reader) are logs of the same shape.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace odonata::dataflash::testing {

/// One field's value: an integer (exact), a floating-point number, or text.
struct Value {
  Value(int v) : integer(v) {}        // NOLINT: implicit, so that records read as lists of values
  Value(long v) : integer(v) {}       // NOLINT
  Value(long long v) : integer(v) {}  // NOLINT
  Value(double v) : number(v), is_float(true) {}    // NOLINT
  Value(const char* t) : text(t), is_text(true) {}  // NOLINT

  long long integer = 0;
  double number = 0.0;
  std::string text;
  bool is_float = false;
  bool is_text = false;
};

class DataflashWriter {
 public:
  /// Starts a log with the FMT record of FMT itself, as ArduPilot does.
  DataflashWriter() { Fmt(128, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns"); }

  /// Writes an FMT record for `type`; `length` 0: the size of `format` plus the 3-byte header.
  /// Returns the record's offset.
  std::size_t Fmt(int type, const std::string& name, const std::string& format,
                  const std::string& labels, int length = 0) {
    const int whole = length != 0 ? length : static_cast<int>(kHeader + PayloadSize(format));
    formats_[type] = format;
    return Record(128, {type, whole, name.c_str(), format.c_str(), labels.c_str()});
  }

  /// Writes a record of `type`, whose FMT was written before; returns its offset.
  std::size_t Record(int type, const std::vector<Value>& values) {
    const auto it = formats_.find(type);
    if (it == formats_.end()) throw std::logic_error("no FMT for type " + std::to_string(type));
    const std::string& format = it->second;
    if (values.size() != format.size()) throw std::logic_error("one value per field");
    const std::size_t offset = bytes_.size();
    bytes_ += std::string{'\xA3', '\x95', static_cast<char>(type)};
    for (std::size_t i = 0; i < format.size(); ++i) Put(format[i], values[i]);
    return offset;
  }

  /// Writes `raw` as it is (garbage, a header of a type without FMT); returns its offset.
  std::size_t Raw(const std::string& raw) {
    const std::size_t offset = bytes_.size();
    bytes_ += raw;
    return offset;
  }

  const std::string& bytes() const { return bytes_; }
  std::size_t size() const { return bytes_.size(); }

  static constexpr std::size_t kHeader = 3;

  /// The payload bytes of `format`'s characters.
  static std::size_t PayloadSize(const std::string& format) {
    std::size_t n = 0;
    for (const char c : format) n += CharSize(c);
    return n;
  }

 private:
  static std::size_t CharSize(char c) {
    switch (c) {
      case 'b':
      case 'B':
      case 'M':
        return 1;
      case 'h':
      case 'H':
      case 'c':
      case 'C':
        return 2;
      case 'i':
      case 'I':
      case 'e':
      case 'E':
      case 'L':
      case 'f':
      case 'n':
        return 4;
      case 'q':
      case 'Q':
      case 'd':
        return 8;
      case 'N':
        return 16;
      case 'Z':
      case 'a':
        return 64;
      default:
        throw std::logic_error(std::string("the writer has no format character ") + c);
    }
  }

  void PutLE(unsigned long long bits, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
      bytes_.push_back(static_cast<char>((bits >> (8 * i)) & 0xffu));
  }

  void Put(char c, const Value& v) {
    const long long integer = v.is_float ? static_cast<long long>(v.number) : v.integer;
    switch (c) {
      case 'f': {
        const float x = static_cast<float>(v.is_float ? v.number : static_cast<double>(v.integer));
        std::uint32_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        return PutLE(bits, 4);
      }
      case 'd': {
        const double x = v.is_float ? v.number : static_cast<double>(v.integer);
        std::uint64_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        return PutLE(bits, 8);
      }
      case 'n':
      case 'N':
      case 'Z': {
        std::string s = v.text.substr(0, CharSize(c));
        s.resize(CharSize(c), '\0');
        bytes_ += s;
        return;
      }
      case 'a':  // element k holds the value plus k
        for (long long k = 0; k < 32; ++k) PutLE(static_cast<unsigned long long>(integer + k), 2);
        return;
      default:
        return PutLE(static_cast<unsigned long long>(integer), CharSize(c));
    }
  }

  std::string bytes_;
  std::map<int, std::string> formats_;
};

/// A short flight: ATT (c and C fields), MODE (M and B), MSG (text). FMTs at 0, 89, 178 and 267;
/// ATT at 356, 386 and 478, MODE at 373 and 495, MSG at 403; 508 bytes. `after_first_att` is
/// written as it is after the first ATT record, at 373.
inline DataflashWriter FlightLog(const std::string& after_first_att = "") {
  DataflashWriter w;
  w.Fmt(129, "ATT", "QccC", "TimeUS,Roll,Pitch,Yaw");
  w.Fmt(130, "MODE", "QMB", "TimeUS,Mode,ModeNum");
  w.Fmt(131, "MSG", "QZ", "TimeUS,Message");
  w.Record(129, {1000000, 150, -250, 35999});
  if (!after_first_att.empty()) w.Raw(after_first_att);
  w.Record(130, {1050000, 5, 5});
  w.Record(129, {1100000, 160, -240, 1});
  w.Record(131, {1150000, "hello"});
  w.Record(129, {1200000, 170, -230, 2});
  w.Record(130, {1250000, 10, 10});
  return w;
}

/// Units as ArduPilot 4 logs them: UNIT, MULT and FMTU records (written after the data, which
/// the reader must not mind) for SENS, whose fields cover the multiplier rules: a c field with
/// multiplier '0', an h field with 'C' (0.001), an H field with '-', an f field with '?'.
inline DataflashWriter UnitsLog() {
  DataflashWriter w;
  w.Fmt(129, "UNIT", "QbZ", "TimeUS,Id,Label");
  w.Fmt(130, "MULT", "Qbd", "TimeUS,Id,Mult");
  w.Fmt(131, "FMTU", "QBNN", "TimeUS,FmtType,UnitIds,MultIds");
  w.Fmt(132, "SENS", "QchHf", "TimeUS,Ang,Fld,Pwm,Acc");
  w.Record(132, {2000000, 4500, 250, 1500, 9.75});
  w.Record(132, {2100000, -4500, -250, 1100, -9.75});
  w.Record(129, {0, 's', "s"});
  w.Record(129, {0, 'd', "deg"});
  w.Record(129, {0, 'G', "Gauss"});
  w.Record(129, {0, 'Y', "us"});
  w.Record(129, {0, 'o', "m/s/s"});
  w.Record(130, {0, '-', 0.0});
  w.Record(130, {0, '?', 1.0});
  w.Record(130, {0, '0', 1.0});
  w.Record(130, {0, 'C', 0.001});
  w.Record(130, {0, 'F', 1e-6});
  w.Record(131, {0, 132, "sdGYo", "F0C-?"});
  return w;
}

/// IMU in two instances, FMTU marking its field I with '#': instance 0 at 1, 2 and 3 ms, instance
/// 1 at 1 and 2 ms; GyrY is minus GyrX.
inline DataflashWriter InstancesLog() {
  DataflashWriter w;
  w.Fmt(129, "FMTU", "QBNN", "TimeUS,FmtType,UnitIds,MultIds");
  w.Fmt(130, "IMU", "QBff", "TimeUS,I,GyrX,GyrY");
  w.Record(129, {0, 130, "s#EE", "F-00"});
  w.Record(130, {1000, 0, 0.5, -0.5});
  w.Record(130, {1000, 1, 1.5, -1.5});
  w.Record(130, {2000, 0, 0.25, -0.25});
  w.Record(130, {2000, 1, 1.25, -1.25});
  w.Record(130, {3000, 0, 0.125, -0.125});
  return w;
}

/// The odd cases: TimeMS with a record whose time goes back (GMB), a message without time (EV), a
/// label given twice (BAT), an int16_t[32] field (ISB), latitude, longitude and an e field (POS).
inline DataflashWriter OddFieldsLog() {
  DataflashWriter w;
  w.Fmt(129, "GMB", "Ihb", "TimeMS,Tq,St");
  w.Fmt(130, "EV", "B", "Id");
  w.Fmt(131, "BAT", "Qff", "TimeUS,Volt,Volt");
  w.Fmt(132, "ISB", "Qa", "TimeUS,x");
  w.Fmt(133, "POS", "QLLe", "TimeUS,Lat,Lng,Alt");
  w.Record(129, {1500, -300, -2});
  w.Record(129, {1400, 10, 1});
  w.Record(129, {1600, 20, 3});
  w.Record(130, {7});
  w.Record(131, {5000000, 12.5, 11.5});
  w.Record(132, {5000000, 100});
  w.Record(133, {5000000, -353632610, 1491652374, 58420});
  return w;
}

}  // namespace odonata::dataflash::testing
