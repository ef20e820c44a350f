#pragma once
// A small ULog writer for the tests: builds files message by message, laid out as PX4's logger
// writes them (little-endian, {uint16 size, uint8 type, payload}), and damaged ones too (cut
// messages, bytes outside any message, wrong sizes). The fuzz harness's seed files
// (tests/fuzz/corpus/ulog_reader) were written with it: EveryMessageKindLog() and small variants.

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace odonata::ulog::testing {

/// The little-endian bytes of a data message's fields, in order.
class Payload {
 public:
  template <typename T>
  Payload& Put(T v) {
    static_assert(std::is_arithmetic_v<T>);
    std::uint64_t bits = 0;
    if constexpr (std::is_same_v<T, float>) {
      std::uint32_t b;
      std::memcpy(&b, &v, sizeof b);
      bits = b;
    } else if constexpr (std::is_same_v<T, double>) {
      std::memcpy(&bits, &v, sizeof bits);
    } else {
      bits = static_cast<std::uint64_t>(v);
    }
    for (std::size_t i = 0; i < sizeof(T); ++i)
      bytes_.push_back(static_cast<char>((bits >> (8 * i)) & 0xffu));
    return *this;
  }
  /// `text` in a char[n] field: cut or NUL-padded to n bytes.
  Payload& Chars(std::string_view text, std::size_t n) {
    std::string s(text.substr(0, n));
    s.resize(n, '\0');
    bytes_ += s;
    return *this;
  }
  Payload& Fill(std::size_t n, char byte = '\0') {
    bytes_.append(n, byte);
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class UlogWriter {
 public:
  struct Written {
    std::size_t offset;
    char type;
  };

  explicit UlogWriter(std::uint8_t version = 1, std::uint64_t start_time_us = 1'000'000) {
    bytes_.assign("ULog\x01\x12\x35", 7);
    bytes_.push_back(static_cast<char>(version));
    bytes_ += Payload().Put(start_time_us).bytes();
  }

  UlogWriter& FlagBits(std::array<std::uint8_t, 8> compat = {},
                       std::array<std::uint8_t, 8> incompat = {},
                       std::array<std::uint64_t, 3> appended_offsets = {},
                       std::size_t extra_bytes = 0) {
    Payload p;
    for (const auto b : compat) p.Put(b);
    for (const auto b : incompat) p.Put(b);
    for (const auto o : appended_offsets) p.Put(o);
    p.Fill(extra_bytes, '\x5a');
    return Message('B', p.bytes());
  }
  /// Sets appended offset `i` of the flag bits message, which must be the first message.
  UlogWriter& SetAppendedOffset(std::size_t i, std::uint64_t offset) {
    if (bytes_.size() < 19 + 40 || bytes_[18] != 'B')
      throw std::logic_error("no flag bits message to set an appended offset in");
    const std::string o = Payload().Put(offset).bytes();
    bytes_.replace(19 + 16 + 8 * i, 8, o);
    return *this;
  }

  UlogWriter& Format(std::string_view text) { return Message('F', text); }

  UlogWriter& Info(std::string_view key, std::string_view value) {
    return Message('I', KeyValue(key, value));
  }
  UlogWriter& InfoText(std::string_view name, std::string_view text) {
    return Info("char[" + std::to_string(text.size()) + "] " + std::string(name), text);
  }
  UlogWriter& MultiInfo(bool continued, std::string_view key, std::string_view value) {
    return Message('M', std::string(1, continued ? '\x01' : '\x00') + KeyValue(key, value));
  }
  UlogWriter& Parameter(std::string_view key, std::string_view value) {
    return Message('P', KeyValue(key, value));
  }
  UlogWriter& ParameterInt(std::string_view name, std::int32_t v) {
    return Parameter("int32_t " + std::string(name), Payload().Put(v).bytes());
  }
  UlogWriter& ParameterFloat(std::string_view name, float v) {
    return Parameter("float " + std::string(name), Payload().Put(v).bytes());
  }
  UlogWriter& DefaultParameterFloat(std::uint8_t default_types, std::string_view name, float v) {
    return Message('Q', std::string(1, static_cast<char>(default_types)) +
                            KeyValue("float " + std::string(name), Payload().Put(v).bytes()));
  }

  UlogWriter& Subscribe(std::uint8_t multi_id, std::uint16_t msg_id, std::string_view topic) {
    return Message('A', Payload().Put(multi_id).Put(msg_id).bytes() + std::string(topic));
  }
  UlogWriter& Unsubscribe(std::uint16_t msg_id) {
    return Message('R', Payload().Put(msg_id).bytes());
  }
  UlogWriter& Data(std::uint16_t msg_id, const Payload& fields) {
    return Message('D', Payload().Put(msg_id).bytes() + fields.bytes());
  }
  UlogWriter& Log(char level, std::uint64_t timestamp_us, std::string_view text) {
    return Message('L', Payload().Put(static_cast<std::uint8_t>(level)).Put(timestamp_us).bytes() +
                            std::string(text));
  }
  UlogWriter& TaggedLog(char level, std::uint16_t tag, std::uint64_t timestamp_us,
                        std::string_view text) {
    return Message(
        'C', Payload().Put(static_cast<std::uint8_t>(level)).Put(tag).Put(timestamp_us).bytes() +
                 std::string(text));
  }
  UlogWriter& Sync() { return Message('S', std::string("\x2f\x73\x13\x20\x25\x0c\xbb\x12", 8)); }
  UlogWriter& Dropout(std::uint16_t duration_ms) {
    return Message('O', Payload().Put(duration_ms).bytes());
  }

  /// Any message, of any type (an unknown one too).
  UlogWriter& Message(char type, std::string_view payload) {
    if (payload.size() > 65535) throw std::logic_error("a ULog message holds at most 65535 bytes");
    written_.push_back(Written{bytes_.size(), type});
    bytes_ += Payload().Put(static_cast<std::uint16_t>(payload.size())).bytes();
    bytes_.push_back(type);
    bytes_.append(payload.data(), payload.size());
    return *this;
  }
  /// A message header claiming `claimed` bytes followed by only the first bytes of `payload`: what
  /// a log cut by a power loss ends with.
  UlogWriter& CutMessage(char type, std::uint16_t claimed, std::string_view partial_payload) {
    bytes_ += Payload().Put(claimed).bytes();
    bytes_.push_back(type);
    bytes_.append(partial_payload.data(), partial_payload.size());
    return *this;
  }
  /// Bytes outside any message.
  UlogWriter& Raw(std::string_view bytes) {
    bytes_.append(bytes.data(), bytes.size());
    return *this;
  }

  std::size_t size() const { return bytes_.size(); }
  const std::string& bytes() const { return bytes_; }
  /// Offset and type of every whole message written, in order.
  const std::vector<Written>& written() const { return written_; }

 private:
  static std::string KeyValue(std::string_view key, std::string_view value) {
    if (key.size() > 255) throw std::logic_error("a key holds at most 255 bytes");
    return std::string(1, static_cast<char>(key.size())) + std::string(key) + std::string(value);
  }

  std::string bytes_;
  std::vector<Written> written_;
};

// The formats of the synthetic logs below: every basic type, a char string, arrays, nested
// formats (one holding padding, one in an array), padding inside and at the end.
inline constexpr std::string_view kVec3Format = "vec3:float x;float y;float z;";
inline constexpr std::string_view kWheelFormat = "wheel:uint16_t rpm;uint8_t[2] _padding0;";
inline constexpr std::string_view kSensorFormat =
    "sensor:uint64_t timestamp;int8_t i8;uint8_t u8;int16_t i16;uint16_t u16;int32_t i32;"
    "uint32_t u32;int64_t i64;uint64_t u64;float f;double d;bool b;char c;char[6] label;"
    "float[4] q;vec3 accel;vec3[2] mags;wheel[2] wheels;uint8_t[3] _padding0;";
inline constexpr std::size_t kSensorSize = 121;        // with the trailing padding
inline constexpr std::size_t kSensorLoggedSize = 118;  // without it
inline constexpr std::string_view kMotorFormat =
    "motor:uint64_t timestamp;float[2] thrust;uint8_t[4] _padding0;";

/// A "sensor" sample: sample k's fields are k-dependent so that each reads back distinctly.
inline Payload SensorSample(std::uint64_t timestamp_us, int k) {
  Payload p;
  p.Put(timestamp_us)
      .Put(static_cast<std::int8_t>(-100 + k))
      .Put(static_cast<std::uint8_t>(200 + k))
      .Put(static_cast<std::int16_t>(-30000 + k))
      .Put(static_cast<std::uint16_t>(60000 + k))
      .Put(static_cast<std::int32_t>(-2000000000 + k))
      .Put(static_cast<std::uint32_t>(4000000000u + static_cast<unsigned>(k)))
      .Put(static_cast<std::int64_t>(-9000000000000000000LL + k))
      .Put(static_cast<std::uint64_t>(18000000000000000000ULL + static_cast<unsigned>(k)))
      .Put(0.25f + static_cast<float>(k))
      .Put(-1e300 * (k + 1))
      .Put(static_cast<std::uint8_t>(k % 2))
      .Put('A')
      .Chars("abc" + std::to_string(k), 6);
  for (int i = 0; i < 4; ++i) p.Put(static_cast<float>(i) + 0.5f * static_cast<float>(k));
  for (int v = 0; v < 3; ++v)  // accel, mags[0], mags[1]
    p.Put(10.0f * v + k).Put(10.0f * v + k + 1).Put(10.0f * v + k + 2);
  for (int w = 0; w < 2; ++w) p.Put(static_cast<std::uint16_t>(1000 * (w + 1) + k)).Fill(2, '\x7f');
  return p;  // the trailing _padding0 is left out, as the logger does
}

inline Payload MotorSample(std::uint64_t timestamp_us, float a, float b, bool with_padding) {
  Payload p;
  p.Put(timestamp_us).Put(a).Put(b);
  if (with_padding) p.Fill(4, '\x11');
  return p;
}

/// A log with every kind of message: flag bits, formats, info, multi-info (one value continued),
/// parameters (initial, changed, default), subscriptions (a topic in two instances), data,
/// logging, tagged logging, sync, dropouts, an unknown message type and an unsubscription.
inline UlogWriter EveryMessageKindLog() {
  UlogWriter w(1, 1'000'000);
  w.FlagBits({1, 0, 0, 0, 0, 0, 0, 0})
      .Format(kSensorFormat)  // used before its nested types are defined: allowed
      .Format(kVec3Format)
      .Format(kWheelFormat)
      .Format(kMotorFormat)
      .InfoText("sys_name", "PX4")
      .Info("uint32_t ver_sw_release", Payload().Put(std::uint32_t{0x010402ff}).bytes())
      .Info("int32_t time_ref_utc", Payload().Put(std::int32_t{-3600}).bytes())
      .Info("float[3] offsets", Payload().Put(1.5f).Put(-2.0f).Put(0.0f).bytes())
      .MultiInfo(false, "char[5] perf", "abcde")
      .MultiInfo(true, "char[3] perf", "fgh")
      .MultiInfo(false, "char[2] perf", "xy")
      .ParameterInt("SYS_AUTOSTART", 4001)
      .ParameterFloat("MC_ROLL_P", 6.5f)
      .DefaultParameterFloat(3, "MC_ROLL_P", 7.0f)
      .Subscribe(0, 0, "sensor")
      .Subscribe(0, 1, "motor")
      .Subscribe(1, 2, "motor")
      .Data(0, SensorSample(1'100'000, 0))
      .Data(1, MotorSample(1'100'500, 0.5f, 0.25f, false))
      .Data(2, MotorSample(1'100'700, 0.75f, 0.125f, true))
      .Log('6', 1'150'000, "[commander] armed")
      .ParameterFloat("MC_ROLL_P", 7.25f)
      .TaggedLog('4', 7, 1'160'000, "low battery")
      .Sync()
      .Dropout(20)
      .Message('X', "a message of a later format version")
      .Data(0, SensorSample(1'200'000, 1))
      .Data(1, MotorSample(1'200'500, 0.5f, 0.5f, true))
      .Data(2, MotorSample(1'200'700, 1.0f, 0.25f, false))
      .Dropout(30)
      .Unsubscribe(2)
      .Data(0, SensorSample(1'300'000, 2));
  return w;
}

}  // namespace odonata::ulog::testing
