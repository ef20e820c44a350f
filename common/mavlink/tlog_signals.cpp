#include "mavlink/tlog_signals.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "cli/parse_command_line.hpp"

namespace odonata::mavlink {
namespace {

struct TlogSignalRef {
  std::string name;
  std::size_t series = 0;  // in TlogFile::series
  std::string field;       // "pitch", "actuator[1]"
  FieldRef ref;
};

struct TlogCatalogue {
  std::vector<TlogSignalRef> signals;                    // as listed
  std::unordered_map<std::string, std::size_t> by_name;  // listed names and the "@" aliases
};

// "ATTITUDE@1:1"
std::string SenderPrefix(const MessageSeries& s) { return s.message->name + "@" + s.sender(); }

timeseries::Interpolation TlogInterpolation(FieldType type) {
  return type == FieldType::kUint8 ? timeseries::Interpolation::kHold
                                   : timeseries::Interpolation::kLinear;
}

void AddSeriesFields(TlogCatalogue& c, const TlogFile& file, std::size_t k, bool is_main) {
  const MessageSeries& s = file.series[k];
  const MessageDef& m = *s.message;
  const std::string prefix = is_main ? m.name : SenderPrefix(s);
  for (const FieldDef& f : m.fields) {
    if (f.type == FieldType::kChar) continue;
    for (std::size_t e = 0; e < f.count(); ++e) {
      const std::string field =
          f.array_length != 0 ? f.name + "[" + std::to_string(e) + "]" : f.name;
      const std::optional<FieldRef> ref = FindField(m, field);
      if (!ref) continue;
      const std::size_t index = c.signals.size();
      std::string name = prefix + "." + field;
      c.by_name.emplace(name, index);
      if (is_main) c.by_name.emplace(SenderPrefix(s) + "." + field, index);
      c.signals.push_back(TlogSignalRef{std::move(name), k, field, *ref});
    }
  }
}

// The series are sorted by message name, then sender: each message's run of them gives the main
// sender's signals first, then the others'.
TlogCatalogue CatalogTlog(const TlogFile& file) {
  TlogCatalogue c;
  const std::vector<MessageSeries>& all = file.series;
  for (std::size_t begin = 0; begin < all.size();) {
    std::size_t end = begin + 1;
    while (end < all.size() && all[end].message == all[begin].message) ++end;
    std::size_t most = begin;
    for (std::size_t k = begin + 1; k < end; ++k)
      if (all[k].size() > all[most].size()) most = k;
    AddSeriesFields(c, file, most, true);
    for (std::size_t k = begin; k < end; ++k)
      if (k != most) AddSeriesFields(c, file, k, false);
    begin = end;
  }
  return c;
}

// The kept frames of one series: times in seconds since the first record, non-decreasing.
struct TlogSeriesTimes {
  std::vector<std::size_t> frames;
  std::vector<double> t_s;
  std::size_t out_of_order = 0;
};

TlogSeriesTimes KeptFrames(const TlogFile& file, const MessageSeries& s) {
  TlogSeriesTimes out;
  out.frames.reserve(s.size());
  out.t_s.reserve(s.size());
  const std::uint64_t zero_us = file.first_time_us;
  std::uint64_t last_us = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const std::uint64_t t_us = s.times_us[i];
    if (!out.frames.empty() && t_us < last_us) {
      ++out.out_of_order;
      continue;
    }
    last_us = t_us;
    out.frames.push_back(i);
    // The difference is exact (below 2^53 µs for any two dates 2000..2100); dividing rounds once.
    out.t_s.push_back(TlogSeconds(t_us, zero_us));
  }
  return out;
}

std::string KnownMessageNames() {
  std::vector<std::string> names;
  for (const MessageDef& m : KnownMessages()) names.push_back(m.name);
  std::sort(names.begin(), names.end());
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// "1:1, 255:190": the senders of `message`.
std::string SendersOf(const TlogFile& file, const std::string& message) {
  std::string out;
  for (const MessageSeries& s : file.series)
    if (s.message->name == message) out += (out.empty() ? "" : ", ") + s.sender();
  return out;
}

// Why `name` names no signal, where the file can tell; "" otherwise.
std::string WhyNoTlogSignal(const TlogFile& file, const std::string& name) {
  const std::size_t dot = name.find('.');
  if (dot == std::string::npos)
    return "signals are named MESSAGE.field, as ATTITUDE.pitchspeed, or "
           "MESSAGE@sysid:compid.field for one sender's";
  const std::string head = name.substr(0, dot);
  const std::size_t at = head.find('@');
  const std::string message = head.substr(0, at);
  const MessageDef* m = FindByName(message);
  if (m == nullptr)
    return "'" + message + "' is no MAVLink message this reader decodes (it decodes " +
           KnownMessageNames() + ")";
  if (file.FrameCount(message) == 0) return "the log has no " + message + " frames";
  if (at != std::string::npos) {
    const std::string sender = head.substr(at + 1);
    const bool sent = std::any_of(file.series.begin(), file.series.end(), [&](const auto& s) {
      return s.message == m && s.sender() == sender;
    });
    if (!sent)
      return "the log has no " + message + " frames from '" + sender +
             "' (a sender is written sysid:compid; " + message + " came from " +
             SendersOf(file, message) + ")";
  }
  const std::string field = name.substr(dot + 1);
  const std::string stem = field.substr(0, field.find('['));
  for (const FieldDef& f : m->fields) {
    if (f.name != stem) continue;
    if (f.type == FieldType::kChar) return "'" + stem + "' is text";
    if (f.array_length != 0)
      return "'" + stem + "' has elements " + stem + "[0] to " + stem + "[" +
             std::to_string(f.count() - 1) + "]";
    if (stem != field) return "'" + stem + "' is one value, no array";
  }
  return "";
}

const TlogSignalRef& FindTlogSignal(const TlogFile& file, const TlogCatalogue& c,
                                    const std::string& name) {
  if (const auto it = c.by_name.find(name); it != c.by_name.end()) return c.signals[it->second];
  std::string message = "no signal '" + name + "' in " + file.source;
  if (const std::string why = WhyNoTlogSignal(file, name); !why.empty())
    message += " (" + why + ")";
  const std::vector<std::string> near = cli::NearestNames(
      name, c.signals, [](const auto& s) -> const std::string& { return s.name; });
  const std::size_t shown = near.size();
  if (shown == 0)
    throw std::invalid_argument(message +
                                "; it has no signals (no frames of a message this "
                                "reader decodes)");
  message += "; nearest: ";
  message += cli::JoinNames(near);
  throw std::invalid_argument(message);
}

}  // namespace

std::vector<SignalInfo> ListSignals(const TlogFile& file) {
  const TlogCatalogue c = CatalogTlog(file);
  struct Timing {
    std::size_t samples = 0, out_of_order = 0;
    double median_rate_hz = 0.0;
  };
  std::vector<Timing> timing;
  timing.reserve(file.series.size());
  for (const MessageSeries& s : file.series) {
    const TlogSeriesTimes t = KeptFrames(file, s);
    timing.push_back(Timing{t.t_s.size(), t.out_of_order, timeseries::MedianRateHz(t.t_s)});
  }
  std::vector<SignalInfo> out;
  out.reserve(c.signals.size());
  for (const TlogSignalRef& sig : c.signals) {
    const MessageSeries& s = file.series[sig.series];
    const Timing& t = timing[sig.series];
    SignalInfo info;
    info.name = sig.name;
    info.message = s.message->name;
    info.sysid = s.sysid;
    info.compid = s.compid;
    info.field = sig.field;
    info.type = TypeName(sig.ref.type);
    info.samples = t.samples;
    info.out_of_order = t.out_of_order;
    info.median_rate_hz = t.median_rate_hz;
    info.interpolation = TlogInterpolation(sig.ref.type);
    out.push_back(std::move(info));
  }
  return out;
}

timeseries::TimedSignal Extract(const TlogFile& file, const std::string& name) {
  const TlogCatalogue c = CatalogTlog(file);
  const TlogSignalRef& sig = FindTlogSignal(file, c, name);
  const MessageSeries& s = file.series[sig.series];
  TlogSeriesTimes kept = KeptFrames(file, s);
  timeseries::TimedSignal out;
  out.name = name;
  out.interpolation = TlogInterpolation(sig.ref.type);
  out.values.reserve(kept.frames.size());
  for (const std::size_t i : kept.frames) out.values.push_back(s.Value(i, sig.ref));
  out.t_s = std::move(kept.t_s);
  return out;
}

}  // namespace odonata::mavlink
