#include "crazyflie_usd/usd_log_signals.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "cli/parse_command_line.hpp"

namespace odonata::crazyflie_usd {
namespace {

struct SignalRef {
  std::string name;  // as listed
  std::size_t type = 0;
  std::size_t variable = 0;
};

struct Catalogue {
  std::vector<SignalRef> signals;
  std::unordered_map<std::string, std::size_t> by_name;  // listed and "eventName:name" names
};

std::string PlainName(const EventType& e, const Variable& v) {
  return v.name.find('.') != std::string::npos ? v.name : e.name + "." + v.name;
}

std::string QualifiedName(const EventType& e, const Variable& v) { return e.name + ":" + v.name; }

timeseries::Interpolation InterpolationOf(char code) {
  return code == 'B' || code == 'b' ? timeseries::Interpolation::kHold
                                    : timeseries::Interpolation::kLinear;
}

Catalogue Catalog(const UsdLogFile& file) {
  struct Candidate {
    std::size_t type = 0, variable = 0;
    std::string plain;
  };
  std::vector<Candidate> all;
  std::unordered_map<std::string, std::size_t> owner;  // plain name -> the candidate keeping it
  for (std::size_t t = 0; t < file.event_types.size(); ++t) {
    const EventType& e = file.event_types[t];
    if (e.size() == 0) continue;
    std::unordered_set<std::string> declared;
    for (std::size_t v = 0; v < e.variables.size(); ++v) {
      if (!declared.insert(e.variables[v].name).second) continue;  // the same values again
      all.push_back(Candidate{t, v, PlainName(e, e.variables[v])});
      const auto [it, added] = owner.emplace(all.back().plain, all.size() - 1);
      // Most records keeps the plain name; on a tie the first declared.
      if (!added && file.event_types[all[it->second].type].size() < e.size())
        it->second = all.size() - 1;
    }
  }
  Catalogue c;
  // Listed names first, so that no alias takes one. A listed name already taken (two event
  // types of one name: a damaged file) stays with the first.
  for (std::size_t i = 0; i < all.size(); ++i) {
    const EventType& e = file.event_types[all[i].type];
    std::string name = owner.at(all[i].plain) == i ? std::move(all[i].plain)
                                                   : QualifiedName(e, e.variables[all[i].variable]);
    if (!c.by_name.emplace(name, c.signals.size()).second) continue;
    c.signals.push_back(SignalRef{std::move(name), all[i].type, all[i].variable});
  }
  for (std::size_t k = 0; k < c.signals.size(); ++k) {
    const EventType& e = file.event_types[c.signals[k].type];
    c.by_name.emplace(QualifiedName(e, e.variables[c.signals[k].variable]), k);
  }
  return c;
}

// Records of `e` kept in time order: one earlier than the last kept is dropped and counted.
std::vector<std::size_t> KeptRecords(const EventType& e, std::size_t& dropped) {
  std::vector<std::size_t> kept;
  kept.reserve(e.size());
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (!kept.empty() && e.time_us[i] < e.time_us[kept.back()]) {
      ++dropped;
      continue;
    }
    kept.push_back(i);
  }
  return kept;
}

// Dividing (not multiplying by 1e-6) rounds once: 100000 µs is exactly the double 0.1.
double Seconds(std::uint64_t t_us) { return static_cast<double>(t_us) / 1e6; }

// Why a name that is no signal may have been asked for, or "".
std::string Hint(const UsdLogFile& file, const std::string& name) {
  const auto ends = [&name](const std::string& tail) {
    return name.size() >= tail.size() &&
           name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
  };
  if (name == "timestamp" || ends(".timestamp") || ends(":timestamp"))
    return " (a record's time is each signal's own time axis, in seconds, not a signal)";
  for (const EventType& e : file.event_types) {
    if (e.size() != 0) continue;
    for (const Variable& v : e.variables)
      if (PlainName(e, v) == name || QualifiedName(e, v) == name)
        return " (event type '" + e.name + "' declares it but logged no record)";
  }
  return "";
}

const SignalRef& Lookup(const UsdLogFile& file, const Catalogue& c, const std::string& name) {
  if (const auto it = c.by_name.find(name); it != c.by_name.end()) return c.signals[it->second];
  const std::string message = "no signal '" + name + "' in " + file.source + Hint(file, name);
  if (c.signals.empty())
    throw std::invalid_argument(message + "; it has no signals (no event type logged a record)");
  const std::vector<std::string> near = cli::NearestNames(
      name, c.signals, [](const auto& s) -> const std::string& { return s.name; });
  throw std::invalid_argument(message + "; nearest: " + cli::JoinNames(near));
}

}  // namespace

std::vector<SignalInfo> ListSignals(const UsdLogFile& file) {
  const Catalogue c = Catalog(file);
  // Every variable of an event type shares its times: timed once per type.
  struct Timing {
    bool done = false;
    std::size_t samples = 0, out_of_order = 0;
    double median_rate_hz = 0.0;
  };
  std::vector<Timing> timing(file.event_types.size());
  std::vector<SignalInfo> out;
  out.reserve(c.signals.size());
  for (const SignalRef& ref : c.signals) {
    const EventType& e = file.event_types[ref.type];
    Timing& t = timing[ref.type];
    if (!t.done) {
      std::vector<double> t_s;
      for (const std::size_t i : KeptRecords(e, t.out_of_order))
        t_s.push_back(Seconds(e.time_us[i]));
      t.samples = t_s.size();
      t.median_rate_hz = timeseries::MedianRateHz(t_s);
      t.done = true;
    }
    const Variable& v = e.variables[ref.variable];
    SignalInfo info;
    info.name = ref.name;
    info.event = e.name;
    info.variable = v.name;
    info.type = TypeName(v.code);
    info.code = v.code;
    info.samples = t.samples;
    info.out_of_order = t.out_of_order;
    info.median_rate_hz = t.median_rate_hz;
    info.interpolation = InterpolationOf(v.code);
    out.push_back(std::move(info));
  }
  return out;
}

timeseries::TimedSignal Extract(const UsdLogFile& file, const std::string& name) {
  const Catalogue c = Catalog(file);
  const SignalRef& ref = Lookup(file, c, name);
  const EventType& e = file.event_types[ref.type];
  timeseries::TimedSignal s;
  s.name = name;
  s.interpolation = InterpolationOf(e.variables[ref.variable].code);
  std::size_t dropped = 0;
  const std::vector<std::size_t> kept = KeptRecords(e, dropped);
  s.t_s.reserve(kept.size());
  s.values.reserve(kept.size());
  for (const std::size_t i : kept) {
    s.t_s.push_back(Seconds(e.time_us[i]));
    s.values.push_back(e.Value(i, ref.variable));
  }
  return s;
}

}  // namespace odonata::crazyflie_usd
