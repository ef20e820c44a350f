#include "dataflash/dataflash_format.hpp"

#include <cstdio>
#include <cstring>

namespace odonata::dataflash {
namespace {

std::string CharLabel(char c) {
  if (c > 0x20 && c < 0x7f) return std::string("'") + c + "'";
  char hex[8];
  std::snprintf(hex, sizeof hex, "0x%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
  return hex;
}

std::vector<std::string> SplitLabels(std::string_view labels) {
  std::vector<std::string> out;
  if (labels.empty()) return out;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = labels.find(',', from);
    out.emplace_back(
        labels.substr(from, comma == std::string_view::npos ? labels.npos : comma - from));
    if (comma == std::string_view::npos) return out;
    from = comma + 1;
  }
}

}  // namespace

std::optional<FormatChar> LookupFormatChar(char c) {
  using K = FieldKind;
  switch (c) {
    case 'b':
      return FormatChar{1, K::kInteger, true, 1.0};
    case 'B':
    case 'M':
      return FormatChar{1, K::kInteger, false, 1.0};
    case 'h':
      return FormatChar{2, K::kInteger, true, 1.0};
    case 'H':
      return FormatChar{2, K::kInteger, false, 1.0};
    case 'i':
      return FormatChar{4, K::kInteger, true, 1.0};
    case 'I':
      return FormatChar{4, K::kInteger, false, 1.0};
    case 'q':
      return FormatChar{8, K::kInteger, true, 1.0};
    case 'Q':
      return FormatChar{8, K::kInteger, false, 1.0};
    case 'c':
      return FormatChar{2, K::kInteger, true, 0.01};
    case 'C':
      return FormatChar{2, K::kInteger, false, 0.01};
    case 'e':
      return FormatChar{4, K::kInteger, true, 0.01};
    case 'E':
      return FormatChar{4, K::kInteger, false, 0.01};
    case 'L':
      return FormatChar{4, K::kInteger, true, 1e-7};
    case 'f':
      return FormatChar{4, K::kFloat, true, 1.0};
    case 'd':
      return FormatChar{8, K::kFloat, true, 1.0};
    case 'n':
      return FormatChar{4, K::kText, false, 1.0};
    case 'N':
      return FormatChar{16, K::kText, false, 1.0};
    case 'Z':
      return FormatChar{64, K::kText, false, 1.0};
    case 'a':
      return FormatChar{64, K::kInt16Array, true, 1.0};
    default:
      return std::nullopt;
  }
}

std::optional<std::size_t> MessageFormat::IndexOf(std::string_view label) const {
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].label == label) return i;
  return std::nullopt;
}

MessageFormat MakeFormat(std::uint8_t type, std::string_view name, std::size_t length,
                         std::string_view format, std::string_view labels) {
  MessageFormat f;
  f.type = type;
  f.name = std::string(name);
  f.length = length;
  f.format = std::string(format);
  f.labels = SplitLabels(labels);
  std::size_t offset = 0;
  for (std::size_t i = 0; i < format.size(); ++i) {
    const std::optional<FormatChar> c = LookupFormatChar(format[i]);
    if (!c) {
      f.undecodable = "format character " + CharLabel(format[i]) + " of \"" + f.format +
                      "\" is none of ArduPilot's";
      break;
    }
    Field field;
    field.label = i < f.labels.size() ? f.labels[i] : std::string();
    field.type = format[i];
    field.offset = offset;
    field.count = c->kind == FieldKind::kInt16Array ? 32 : 1;
    f.fields.push_back(std::move(field));
    offset += c->size;
  }
  if (f.undecodable.empty() && offset > f.payload_size())
    f.undecodable = "format \"" + f.format + "\" needs " + std::to_string(offset) +
                    " payload bytes, the length of " + std::to_string(length) + " gives " +
                    std::to_string(f.payload_size());
  if (!f.undecodable.empty()) f.fields.clear();
  return f;
}

MessageFormat FmtFormat() {
  return MakeFormat(kFmtType, "FMT", kFmtLength, "BBnNZ", "Type,Length,Name,Format,Columns");
}

std::string CString(std::string_view chars) {
  return std::string(chars.substr(0, chars.find('\0')));
}

double RawValue(const std::uint8_t* payload, const Field& field, std::size_t element) {
  const FormatChar c = *LookupFormatChar(field.type);
  const std::size_t size = c.kind == FieldKind::kInt16Array ? 2 : c.size;
  const std::uint8_t* p = payload + field.offset + element * size;
  const std::uint64_t bits = ReadUnsignedLE(p, size);
  if (c.kind == FieldKind::kFloat) {
    if (size == 4) {
      const auto narrow = static_cast<std::uint32_t>(bits);
      float v;
      std::memcpy(&v, &narrow, sizeof v);
      return v;
    }
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  if (!c.is_signed) return static_cast<double>(bits);
  // Sign-extends the `size`-byte two's complement number.
  const std::uint64_t sign = std::uint64_t{1} << (8 * size - 1);
  return static_cast<double>(static_cast<std::int64_t>((bits ^ sign) - sign));
}

std::string FieldText(const std::uint8_t* payload, const Field& field) {
  const FormatChar c = *LookupFormatChar(field.type);
  return CString(std::string_view(reinterpret_cast<const char*>(payload) + field.offset, c.size));
}

}  // namespace odonata::dataflash
