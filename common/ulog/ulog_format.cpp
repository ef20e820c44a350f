#include "ulog/ulog_format.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <set>
#include <utility>

namespace odonata::ulog {
namespace {

struct BasicTypeInfo {
  const char* name;
  BasicType type;
  std::size_t size;
};

constexpr BasicTypeInfo kBasicTypes[] = {
    {"int8_t", BasicType::kInt8, 1},   {"uint8_t", BasicType::kUint8, 1},
    {"int16_t", BasicType::kInt16, 2}, {"uint16_t", BasicType::kUint16, 2},
    {"int32_t", BasicType::kInt32, 4}, {"uint32_t", BasicType::kUint32, 4},
    {"int64_t", BasicType::kInt64, 8}, {"uint64_t", BasicType::kUint64, 8},
    {"float", BasicType::kFloat, 4},   {"double", BasicType::kDouble, 8},
    {"bool", BasicType::kBool, 1},     {"char", BasicType::kChar, 1},
};

// SizeOf and TypeName index the table by the enumerator.
constexpr bool TableFollowsTheEnum() {
  for (std::size_t i = 0; i < std::size(kBasicTypes); ++i)
    if (static_cast<std::size_t>(kBasicTypes[i].type) != i) return false;
  return true;
}
static_assert(TableFollowsTheEnum());

// Nesting deeper than this is no real log: it only bounds the recursion a hostile file can ask for.
constexpr int kMaxNesting = 32;

std::string Quoted(std::string_view s) { return "'" + std::string(s) + "'"; }

// Names end up in signal names ("topic/1.inner[2].x"): the characters that structure those, and
// blanks or control bytes, are refused so that every name reads back unambiguously.
bool IsNameByte(unsigned char c) {
  if (c <= 0x20 || c == 0x7f) return false;
  return c != ';' && c != ':' && c != '[' && c != ']' && c != '.';
}

void CheckName(std::string_view name, std::string_view what) {
  if (name.empty()) throw UlogError(std::string(what) + " is empty");
  for (const char c : name)
    if (!IsNameByte(static_cast<unsigned char>(c)))
      throw UlogError(std::string(what) + " " + Quoted(name) + " holds the character " +
                      (static_cast<unsigned char>(c) < 0x21 ? "with code " + std::to_string(+c)
                                                            : Quoted(std::string_view(&c, 1))));
}

std::string_view TrimBlanks(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Sizes of formats, memoised, with the chain being resolved kept to name a cycle.
class LayoutResolver {
 public:
  LayoutResolver(const std::map<std::string, Format>& formats, std::size_t& budget)
      : formats_(formats), budget_(budget) {}

  const Format& Get(const std::string& name, const std::string& used_by) const {
    const auto it = formats_.find(name);
    if (it == formats_.end())
      throw UlogError("no format message defines " + Quoted(name) +
                      (used_by.empty() ? "" : " (used in " + Quoted(used_by) + ")"));
    return it->second;
  }

  std::size_t SizeOfFormat(const std::string& name, const std::string& used_by, int depth) {
    if (const auto it = sizes_.find(name); it != sizes_.end()) return it->second;
    if (std::find(chain_.begin(), chain_.end(), name) != chain_.end()) {
      std::string cycle;
      for (const auto& n : chain_) cycle += n + " -> ";
      throw UlogError("format " + Quoted(name) + " contains itself (" + cycle + name + ")");
    }
    if (depth > kMaxNesting)
      throw UlogError("formats nest deeper than " + std::to_string(kMaxNesting) + " at " +
                      Quoted(name));
    const Format& f = Get(name, used_by);
    chain_.push_back(name);
    std::size_t total = 0;
    for (const auto& field : f.fields) {
      const auto basic = ParseBasicType(field.type.name);
      const std::size_t element =
          basic ? SizeOf(*basic) : SizeOfFormat(field.type.name, name, depth + 1);
      total += element * field.type.count();  // both <= 65535: no overflow in 64 bits
      if (total > kMaxMessagePayload)
        throw UlogError("format " + Quoted(name) + " is larger than a message can hold (" +
                        std::to_string(kMaxMessagePayload) + " bytes)");
    }
    chain_.pop_back();
    sizes_.emplace(name, total);
    return total;
  }

  void Expand(const Format& f, const std::string& prefix, std::size_t base,
              std::vector<FieldLayout>& out, int depth) {
    std::size_t offset = base;
    for (const auto& field : f.fields) {
      const std::size_t n = field.type.count();
      if (const auto basic = ParseBasicType(field.type.name)) {
        // A zero-length array holds no byte to read: no field, so a field is at least one byte
        // and a layout has at most as many fields as bytes.
        if (!field.IsPadding() && n > 0) {
          Spend();
          out.push_back(FieldLayout{prefix + field.name, *basic, offset, n,
                                    field.type.array_length.has_value()});
        }
        offset += SizeOf(*basic) * n;
        continue;
      }
      const std::size_t element = sizes_.at(field.type.name);
      if (!field.IsPadding() && element > 0) {
        const Format& inner = formats_.at(field.type.name);
        for (std::size_t i = 0; i < n; ++i) {
          const std::string index =
              field.type.array_length ? "[" + std::to_string(i) + "]" : std::string();
          Expand(inner, prefix + field.name + index + ".", offset + i * element, out, depth + 1);
        }
      }
      offset += element * n;
    }
  }

 private:
  void Spend() {
    if (budget_ == 0)
      throw UlogError("the formats expand to more fields than this reader holds for one file");
    --budget_;
  }

  const std::map<std::string, Format>& formats_;
  std::size_t& budget_;
  std::map<std::string, std::size_t> sizes_;
  std::vector<std::string> chain_;
};

}  // namespace

std::optional<BasicType> ParseBasicType(std::string_view name) {
  for (const auto& t : kBasicTypes)
    if (name == t.name) return t.type;
  return std::nullopt;
}

std::size_t SizeOf(BasicType type) { return kBasicTypes[static_cast<std::size_t>(type)].size; }

const char* TypeName(BasicType type) { return kBasicTypes[static_cast<std::size_t>(type)].name; }

TypeRef ParseTypeRef(std::string_view text) {
  TypeRef t;
  const auto open = text.find('[');
  if (open == std::string_view::npos) {
    CheckName(text, "type name");
    t.name = std::string(text);
    return t;
  }
  if (text.back() != ']') throw UlogError("type " + Quoted(text) + " is not of the form name[N]");
  const std::string_view digits = text.substr(open + 1, text.size() - open - 2);
  // Five digits reach 99999, past any size a message can hold; longer would only overflow.
  if (digits.empty() || digits.size() > 5 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    throw UlogError("type " + Quoted(text) + " has no array length of at most 5 digits");
  std::size_t n = 0;
  for (const char c : digits) n = n * 10 + static_cast<std::size_t>(c - '0');
  if (n > kMaxMessagePayload)
    throw UlogError("type " + Quoted(text) + " has more elements than a message can hold");
  CheckName(text.substr(0, open), "type name");
  t.name = std::string(text.substr(0, open));
  t.array_length = n;
  return t;
}

Format ParseFormat(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos)
    throw UlogError("format " + Quoted(text.substr(0, 60)) + " has no ':' after its name");
  Format f;
  CheckName(text.substr(0, colon), "format name");
  f.name = std::string(text.substr(0, colon));
  if (ParseBasicType(f.name))
    throw UlogError("format " + Quoted(f.name) + " has the name of a basic type");
  std::string_view rest = text.substr(colon + 1);
  std::set<std::string_view> seen;
  while (!rest.empty()) {
    const auto semi = rest.find(';');
    const std::string_view piece = TrimBlanks(rest.substr(0, semi));
    rest = semi == std::string_view::npos ? std::string_view() : rest.substr(semi + 1);
    if (piece.empty()) continue;  // the ';' after the last field
    const auto blank = piece.find_last_of(" \t");
    if (blank == std::string_view::npos)
      throw UlogError("field " + Quoted(piece) + " of format " + Quoted(f.name) +
                      " is not 'type name'");
    FormatField field;
    field.type = ParseTypeRef(TrimBlanks(piece.substr(0, blank)));
    const std::string_view name = piece.substr(blank + 1);
    CheckName(name, "field name");
    if (!seen.insert(name).second)
      throw UlogError("field " + Quoted(name) + " appears twice in format " + Quoted(f.name));
    field.name = std::string(name);
    f.fields.push_back(std::move(field));
  }
  if (f.fields.empty()) throw UlogError("format " + Quoted(f.name) + " has no field");
  return f;
}

const FieldLayout* Layout::Find(std::string_view path) const {
  for (const auto& f : fields)
    if (f.path == path) return &f;
  return nullptr;
}

Layout ResolveLayout(const std::string& name, const std::map<std::string, Format>& formats,
                     std::size_t& field_budget) {
  LayoutResolver resolver(formats, field_budget);
  Layout layout;
  layout.name = name;
  layout.size = resolver.SizeOfFormat(name, "", 0);
  const Format& f = resolver.Get(name, "");
  resolver.Expand(f, "", 0, layout.fields, 0);

  // The logger leaves out the padding at the end; a nested format keeps its own.
  layout.logged_size = layout.size;
  for (auto it = f.fields.rbegin(); it != f.fields.rend() && it->IsPadding(); ++it) {
    const auto basic = ParseBasicType(it->type.name);
    const std::size_t element =
        basic ? SizeOf(*basic) : resolver.SizeOfFormat(it->type.name, name, 1);
    layout.logged_size -= element * it->type.count();
  }

  const FieldLayout* ts = layout.Find("timestamp");
  if (ts == nullptr || ts->type != BasicType::kUint64 || ts->is_array)
    throw UlogError("format " + Quoted(name) +
                    " has no 'uint64_t timestamp' field, which every logged format needs");
  layout.timestamp_offset = ts->offset;
  return layout;
}

double ReadAsDouble(const std::uint8_t* p, BasicType type) {
  switch (type) {
    case BasicType::kInt8:
      return static_cast<std::int8_t>(p[0]);
    case BasicType::kUint8:
    case BasicType::kChar:
      return p[0];
    case BasicType::kBool:
      return p[0] != 0 ? 1.0 : 0.0;
    case BasicType::kInt16:
      return static_cast<std::int16_t>(static_cast<std::uint16_t>(ReadUnsignedLE(p, 2)));
    case BasicType::kUint16:
      return static_cast<double>(ReadUnsignedLE(p, 2));
    case BasicType::kInt32:
      return static_cast<std::int32_t>(static_cast<std::uint32_t>(ReadUnsignedLE(p, 4)));
    case BasicType::kUint32:
      return static_cast<double>(ReadUnsignedLE(p, 4));
    case BasicType::kInt64:
      return static_cast<double>(static_cast<std::int64_t>(ReadUnsignedLE(p, 8)));
    case BasicType::kUint64:
      return static_cast<double>(ReadUnsignedLE(p, 8));
    case BasicType::kFloat: {
      const auto bits = static_cast<std::uint32_t>(ReadUnsignedLE(p, 4));
      float v;
      std::memcpy(&v, &bits, sizeof v);
      return v;
    }
    case BasicType::kDouble: {
      const std::uint64_t bits = ReadUnsignedLE(p, 8);
      double v;
      std::memcpy(&v, &bits, sizeof v);
      return v;
    }
  }
  return 0.0;  // not reached: every enumerator is handled above
}

}  // namespace odonata::ulog
