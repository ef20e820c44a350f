#include "dataflash/dataflash_signals.hpp"

#include <algorithm>
#include <limits>
#include <optional>
#include <set>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "cli/parse_command_line.hpp"

namespace odonata::dataflash {
namespace {

// The records of one message with one instance number.
struct MessageSeries {
  std::string prefix;  // "IMU" or "IMU[1]"
  std::string message;
  const MessageFormat* format = nullptr;
  const MessageRecords* records = nullptr;
  std::optional<std::size_t> instance_field;
  int instance = -1;  // with instance_field: the records kept are those of this number
  std::size_t time_field = 0;
  double time_divisor = 1e6;  // to seconds: 1e6 for TimeUS, 1e3 for TimeMS
};

struct SeriesSignal {
  std::string name;
  std::size_t series = 0;
  std::size_t field = 0;
  std::size_t element = 0;
};

struct SignalCatalogue {
  std::vector<MessageSeries> series;
  std::vector<SeriesSignal> signals;
  std::unordered_map<std::string, std::size_t> by_name;  // listed names and "IMU[0]." aliases
};

FieldKind FieldKindOf(const Field& f) { return LookupFormatChar(f.type)->kind; }

// The field of a message's time and its divisor to seconds, or nullopt.
std::optional<std::pair<std::size_t, double>> TimeField(const MessageFormat& f) {
  for (const auto& [label, divisor] : {std::pair{"TimeUS", 1e6}, std::pair{"TimeMS", 1e3}}) {
    const std::optional<std::size_t> i = f.IndexOf(label);
    // An unscaled integer: c C e E L are no times.
    if (i && FieldKindOf(f.fields[*i]) == FieldKind::kInteger &&
        LookupFormatChar(f.fields[*i].type)->scale == 1.0)
      return std::pair{*i, divisor};
  }
  return std::nullopt;
}

// The format character's scale where it has one, else FMTU's multiplier (see the header).
double MultiplierFor(const DataflashFile& file, const MessageFormat& f, std::size_t field) {
  const double scale = LookupFormatChar(f.fields[field].type)->scale;
  if (scale != 1.0) return scale;
  return file.MultiplierOf(f, field).value_or(1.0);
}

// Flags, small enumerations and flight modes hold until their next record.
timeseries::Interpolation InterpolationOf(const Field& f) {
  return f.type == 'b' || f.type == 'B' || f.type == 'M' ? timeseries::Interpolation::kHold
                                                         : timeseries::Interpolation::kLinear;
}

void AddSeriesSignals(SignalCatalogue& c, MessageSeries series) {
  const std::size_t s = c.series.size();
  const MessageFormat& f = *series.format;
  const bool aliased = series.instance_field && series.instance == 0;
  for (std::size_t i = 0; i < f.fields.size(); ++i) {
    const Field& field = f.fields[i];
    if (i == series.time_field || (series.instance_field && i == *series.instance_field) ||
        field.label.empty() || FieldKindOf(field) == FieldKind::kText)
      continue;
    for (std::size_t e = 0; e < field.count; ++e) {
      std::string suffix = "." + field.label;
      if (field.count > 1) suffix += "[" + std::to_string(e) + "]";
      std::string name = series.prefix + suffix;
      // A label given twice names its first field only.
      if (!c.by_name.emplace(name, c.signals.size()).second) continue;
      if (aliased) c.by_name.emplace(series.message + "[0]" + suffix, c.signals.size());
      c.signals.push_back(SeriesSignal{std::move(name), s, i, e});
    }
  }
  c.series.push_back(std::move(series));
}

SignalCatalogue Catalog(const DataflashFile& file) {
  SignalCatalogue c;
  for (const auto& [name, records] : file.messages) {
    const auto it = file.formats.find(records.type);
    if (records.size() == 0 || it == file.formats.end() || !it->second.decodable()) continue;
    const MessageFormat& f = it->second;
    const auto time_field = TimeField(f);
    if (!time_field) continue;
    MessageSeries base{
        name, name, &f, &records, file.InstanceField(f), -1, time_field->first, time_field->second};
    if (!base.instance_field) {
      AddSeriesSignals(c, std::move(base));
      continue;
    }
    // Only instances that logged records have signals: the names stay bounded by the records.
    std::set<int> instances;
    for (const std::uint64_t offset : records.offsets)
      instances.insert(
          static_cast<int>(RawValue(file.Payload(offset), f.fields[*base.instance_field])));
    for (const int k : instances) {
      MessageSeries series = base;
      series.instance = k;
      if (k != 0) series.prefix = name + "[" + std::to_string(k) + "]";
      AddSeriesSignals(c, std::move(series));
    }
  }
  return c;
}

// The kept records of one series: times in seconds, non-decreasing.
struct SeriesTimes {
  std::vector<std::uint64_t> offsets;
  std::vector<double> t_s;
  std::size_t out_of_order = 0;
};

SeriesTimes TimesOf(const DataflashFile& file, const MessageSeries& s) {
  SeriesTimes out;
  const MessageFormat& f = *s.format;
  double last_s = -std::numeric_limits<double>::infinity();
  for (const std::uint64_t offset : s.records->offsets) {
    const std::uint8_t* p = file.Payload(offset);
    if (s.instance_field &&
        static_cast<int>(RawValue(p, f.fields[*s.instance_field])) != s.instance)
      continue;
    // Dividing (not multiplying by 1e-6) rounds once: 100000 µs is exactly the double 0.1.
    const double t_s = RawValue(p, f.fields[s.time_field]) / s.time_divisor;
    if (t_s < last_s) {
      ++out.out_of_order;
      continue;
    }
    last_s = t_s;
    out.offsets.push_back(offset);
    out.t_s.push_back(t_s);
  }
  return out;
}

// Why `name` names no signal, where the file can tell; "" otherwise.
std::string WhyNoSignal(const DataflashFile& file, const std::string& name) {
  const std::size_t dot = name.find('.');
  if (dot == std::string::npos) return "signals are named MESSAGE.FIELD, as ATT.Pitch";
  const std::string message = name.substr(0, std::min(dot, name.find('[')));
  const MessageFormat* f = file.FindFormat(message);
  if (!f) return "";
  const std::string quoted = "message '" + message + "'";
  if (!f->decodable()) return quoted + " cannot be decoded: " + f->undecodable;
  if (file.RecordCount(message) == 0) return quoted + " has an FMT but no records";
  const auto time_field = TimeField(*f);
  if (!time_field) return quoted + " has no TimeUS or TimeMS field: its values have no time";
  std::string label = name.substr(dot + 1);
  label = label.substr(0, label.find('['));
  const std::optional<std::size_t> i = f->IndexOf(label);
  if (!i) return "";
  const Field& field = f->fields[*i];
  const std::optional<std::size_t> instance_field = file.InstanceField(*f);
  if (FieldKindOf(field) == FieldKind::kText) return "'" + label + "' is text";
  if (*i == time_field->first) return "'" + label + "' is the time of the other fields";
  if (instance_field == i)
    return "'" + label + "' is the instance number: instance k is named " + message + "[k]." +
           "FIELD, instance 0 also " + message + ".FIELD";
  if (field.count > 1)
    return "'" + label + "' has elements " + label + "[0] to " + label + "[" +
           std::to_string(field.count - 1) + "]";
  if (instance_field || name.find('[') < dot) return quoted + " has no records of that instance";
  return "";
}

const SeriesSignal& FindSignal(const DataflashFile& file, const SignalCatalogue& c,
                               const std::string& name) {
  if (const auto it = c.by_name.find(name); it != c.by_name.end()) return c.signals[it->second];
  std::string message = "no signal '" + name + "' in " + file.source;
  if (const std::string why = WhyNoSignal(file, name); !why.empty()) message += " (" + why + ")";
  const std::vector<std::string> near = cli::NearestNames(
      name, c.signals, [](const auto& s) -> const std::string& { return s.name; });
  const std::size_t shown = near.size();
  if (shown == 0) throw std::invalid_argument(message + "; it has no numeric signals");
  message += "; nearest: ";
  message += cli::JoinNames(near);
  throw std::invalid_argument(message);
}

}  // namespace

std::vector<SignalInfo> ListSignals(const DataflashFile& file) {
  const SignalCatalogue c = Catalog(file);
  struct Timing {
    std::size_t samples = 0, out_of_order = 0;
    double median_rate_hz = 0.0;
  };
  std::vector<Timing> timing;
  timing.reserve(c.series.size());
  for (const MessageSeries& s : c.series) {
    const SeriesTimes t = TimesOf(file, s);
    timing.push_back(Timing{t.t_s.size(), t.out_of_order, timeseries::MedianRateHz(t.t_s)});
  }
  std::vector<SignalInfo> out;
  out.reserve(c.signals.size());
  for (const SeriesSignal& sig : c.signals) {
    const MessageSeries& s = c.series[sig.series];
    const MessageFormat& f = *s.format;
    const Timing& t = timing[sig.series];
    SignalInfo info;
    info.name = sig.name;
    info.message = s.message;
    info.instance = s.instance;
    info.unit = file.UnitOf(f, sig.field);
    info.multiplier = MultiplierFor(file, f, sig.field);
    info.samples = t.samples;
    info.out_of_order = t.out_of_order;
    info.median_rate_hz = t.median_rate_hz;
    info.interpolation = InterpolationOf(f.fields[sig.field]);
    out.push_back(std::move(info));
  }
  return out;
}

timeseries::TimedSignal Extract(const DataflashFile& file, const std::string& name) {
  const SignalCatalogue c = Catalog(file);
  const SeriesSignal& sig = FindSignal(file, c, name);
  const MessageSeries& s = c.series[sig.series];
  const Field& field = s.format->fields[sig.field];
  const double multiplier = MultiplierFor(file, *s.format, sig.field);
  SeriesTimes times = TimesOf(file, s);
  timeseries::TimedSignal out;
  out.name = name;
  out.interpolation = InterpolationOf(field);
  out.values.reserve(times.offsets.size());
  for (const std::uint64_t offset : times.offsets)
    out.values.push_back(RawValue(file.Payload(offset), field, sig.element) * multiplier);
  out.t_s = std::move(times.t_s);
  return out;
}

}  // namespace odonata::dataflash
