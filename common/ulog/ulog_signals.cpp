#include "ulog/ulog_signals.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "cli/parse_command_line.hpp"

namespace odonata::ulog {
namespace {

// One topic instance: its subscriptions (more than one only if a file subscribed it again under
// another msg_id) share the format, so their samples make one series.
struct TopicInstance {
  std::string prefix;  // "topic" or "topic/N"
  std::vector<const Subscription*> subscriptions;
  const Layout& layout() const { return *subscriptions.front()->layout; }
  bool HasSamples() const {
    return std::any_of(subscriptions.begin(), subscriptions.end(),
                       [](const Subscription* s) { return s->size() > 0; });
  }
};

struct SignalRef {
  std::string name;
  std::size_t instance = 0;
  const FieldLayout* field = nullptr;
  std::size_t element = 0;
};

struct Catalogue {
  std::vector<TopicInstance> instances;
  std::vector<SignalRef> signals;
  std::unordered_map<std::string, std::size_t> by_name;
};

bool IsSignalField(const FieldLayout& f) {
  return f.type != BasicType::kChar && f.path != "timestamp";
}

Catalogue Catalog(const UlogFile& file) {
  Catalogue c;
  std::map<std::pair<std::string, int>, std::size_t> index;
  for (const auto& s : file.subscriptions) {
    const auto [it, added] =
        index.emplace(std::make_pair(s.topic, int{s.multi_id}), c.instances.size());
    if (added)
      c.instances.push_back(TopicInstance{
          s.multi_id == 0 ? s.topic : s.topic + "/" + std::to_string(s.multi_id), {}});
    c.instances[it->second].subscriptions.push_back(&s);
  }
  for (std::size_t i = 0; i < c.instances.size(); ++i) {
    const TopicInstance& ti = c.instances[i];
    // Only topics with samples have signals. This also bounds the names to the bytes of data
    // read: a format of 60000 fields subscribed in 256 instances, without data, names nothing.
    if (!ti.HasSamples()) continue;
    for (const FieldLayout& f : ti.layout().fields) {
      if (!IsSignalField(f)) continue;
      for (std::size_t e = 0; e < f.count; ++e) {
        std::string name = ti.prefix + "." + f.path;
        if (f.is_array) name += "[" + std::to_string(e) + "]";
        // Topic names may hold '/': "a/1" instance 0 and "a" instance 1 would share names. The
        // first keeps them; no real log does this.
        if (c.by_name.emplace(name, c.signals.size()).second)
          c.signals.push_back(SignalRef{std::move(name), i, &f, e});
      }
    }
  }
  return c;
}

// A signal's kept samples: times in µs as logged, and values.
struct Series {
  std::vector<std::uint64_t> t_us;
  std::vector<double> values;
  std::size_t out_of_order = 0;
};

// Sample indices of one subscription kept in time order: a sample earlier than the last kept one
// is dropped.
std::vector<std::size_t> KeptSamples(const Subscription& s, std::size_t& dropped) {
  std::vector<std::size_t> kept;
  kept.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!kept.empty() && s.timestamps_us[i] < s.timestamps_us[kept.back()]) {
      ++dropped;
      continue;
    }
    kept.push_back(i);
  }
  return kept;
}

// (subscription, sample) pairs of a topic instance in time order: each subscription's kept
// samples, merged stably when there are several.
std::vector<std::pair<const Subscription*, std::size_t>> Timeline(const TopicInstance& ti,
                                                                  std::size_t& dropped) {
  std::vector<std::pair<const Subscription*, std::size_t>> all;
  for (const Subscription* s : ti.subscriptions) {
    const std::size_t before = all.size();
    for (const std::size_t i : KeptSamples(*s, dropped)) all.emplace_back(s, i);
    if (before > 0) {
      const auto earlier = [](const auto& a, const auto& b) {
        return a.first->timestamps_us[a.second] < b.first->timestamps_us[b.second];
      };
      std::inplace_merge(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(before), all.end(),
                         earlier);
    }
  }
  return all;
}

Series SeriesOf(const Catalogue& c, const SignalRef& ref) {
  Series out;
  const auto timeline = Timeline(c.instances[ref.instance], out.out_of_order);
  out.t_us.reserve(timeline.size());
  out.values.reserve(timeline.size());
  for (const auto& [s, i] : timeline) {
    out.t_us.push_back(s->timestamps_us[i]);
    out.values.push_back(s->Value(i, *ref.field, ref.element));
  }
  return out;
}

double MedianRateHz(const std::vector<std::uint64_t>& t_us) {
  std::vector<std::uint64_t> dt;
  dt.reserve(t_us.size());
  for (std::size_t i = 1; i < t_us.size(); ++i)
    if (t_us[i] > t_us[i - 1]) dt.push_back(t_us[i] - t_us[i - 1]);
  if (dt.empty()) return 0.0;
  const auto mid = dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2);
  std::nth_element(dt.begin(), mid, dt.end());
  double median = static_cast<double>(*mid);
  if (dt.size() % 2 == 0)
    median = 0.5 * (median + static_cast<double>(*std::max_element(dt.begin(), mid)));
  return 1e6 / median;
}

double MeanRateHz(const std::vector<std::uint64_t>& t_us) {
  if (t_us.size() < 2 || t_us.back() <= t_us.front()) return 0.0;
  return static_cast<double>(t_us.size() - 1) * 1e6 /
         static_cast<double>(t_us.back() - t_us.front());
}

// Seconds from the file's start to `t_us`, negative for a time before it, exact to the µs.
double SecondsSince(std::uint64_t start_us, std::uint64_t t_us) {
  // Dividing (not multiplying by 1e-6) rounds once: 100000 µs is exactly the double 0.1.
  return t_us >= start_us ? static_cast<double>(t_us - start_us) / 1e6
                          : -static_cast<double>(start_us - t_us) / 1e6;
}

const SignalRef& Lookup(const UlogFile& file, const Catalogue& c, const std::string& name) {
  if (const auto it = c.by_name.find(name); it != c.by_name.end()) return c.signals[it->second];
  std::vector<std::pair<std::size_t, const std::string*>> near;
  near.reserve(c.signals.size());
  for (const auto& s : c.signals) near.emplace_back(cli::EditDistance(name, s.name), &s.name);
  const std::size_t shown = std::min<std::size_t>(5, near.size());
  std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(shown), near.end(),
                    [](const auto& a, const auto& b) {
                      return a.first != b.first ? a.first < b.first : *a.second < *b.second;
                    });
  std::string message = "no signal '" + name + "' in " + file.source;
  const std::string prefix = name.substr(0, name.find('.'));
  for (const auto& ti : c.instances)
    if (ti.prefix == prefix && !ti.HasSamples())
      throw std::invalid_argument(message + ": topic '" + prefix +
                                  "' is subscribed but has no samples");
  if (shown == 0) throw std::invalid_argument(message + " (it has no numeric signals)");
  message += "; nearest: ";
  for (std::size_t i = 0; i < shown; ++i) message += (i ? ", " : "") + *near[i].second;
  throw std::invalid_argument(message);
}

}  // namespace

std::vector<SignalInfo> ListSignals(const UlogFile& file) {
  const Catalogue c = Catalog(file);
  struct InstanceTiming {
    std::size_t samples = 0, out_of_order = 0;
    double median_hz = 0.0, mean_hz = 0.0;
  };
  std::vector<InstanceTiming> timing(c.instances.size());
  for (std::size_t i = 0; i < c.instances.size(); ++i) {
    InstanceTiming& t = timing[i];
    std::vector<std::uint64_t> t_us;
    for (const auto& [s, k] : Timeline(c.instances[i], t.out_of_order))
      t_us.push_back(s->timestamps_us[k]);
    t.samples = t_us.size();
    t.median_hz = MedianRateHz(t_us);
    t.mean_hz = MeanRateHz(t_us);
  }
  std::vector<SignalInfo> out;
  for (const auto& ref : c.signals) {
    const InstanceTiming& t = timing[ref.instance];
    if (t.samples == 0) continue;
    const Subscription& s = *c.instances[ref.instance].subscriptions.front();
    out.push_back(SignalInfo{ref.name, s.topic, s.multi_id, TypeName(ref.field->type), t.samples,
                             t.out_of_order, t.median_hz, t.mean_hz});
  }
  return out;
}

SignalSamples Extract(const UlogFile& file, const std::string& name) {
  const Catalogue c = Catalog(file);
  Series s = SeriesOf(c, Lookup(file, c, name));
  SignalSamples out;
  out.name = name;
  out.out_of_order = s.out_of_order;
  out.values = std::move(s.values);
  out.t_s.reserve(s.t_us.size());
  for (const std::uint64_t t : s.t_us) out.t_s.push_back(SecondsSince(file.start_time_us, t));
  return out;
}

ResampledSignals Resample(const UlogFile& file, const std::vector<std::string>& names,
                          double rate_hz, int max_gap) {
  if (names.empty()) throw std::invalid_argument("resampling needs at least one signal");
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (names[i] == names[j])
        throw std::invalid_argument("signal '" + names[i] + "' is asked for twice");
  if (!std::isfinite(rate_hz) || rate_hz < 0.0)
    throw std::invalid_argument(
        "the resampling rate must be a finite number of Hz >= 0 (0: the "
        "fastest signal's), not " +
        std::to_string(rate_hz));
  if (max_gap < 0)
    throw std::invalid_argument("max_gap must be >= 0, not " + std::to_string(max_gap));

  const Catalogue c = Catalog(file);
  std::vector<Series> series;
  series.reserve(names.size());
  double fastest_hz = 0.0;
  std::uint64_t begin_us = 0, end_us = std::numeric_limits<std::uint64_t>::max();
  for (const auto& name : names) {
    series.push_back(SeriesOf(c, Lookup(file, c, name)));
    const Series& s = series.back();
    if (s.t_us.empty()) throw std::invalid_argument("signal '" + name + "' has no samples");
    fastest_hz = std::max(fastest_hz, MedianRateHz(s.t_us));
    begin_us = std::max(begin_us, s.t_us.front());
    end_us = std::min(end_us, s.t_us.back());
  }
  if (end_us < begin_us)
    throw std::invalid_argument("the signals' time spans do not overlap (the latest starts " +
                                std::to_string(SecondsSince(file.start_time_us, begin_us)) +
                                " s after the file's start, the earliest ends at " +
                                std::to_string(SecondsSince(file.start_time_us, end_us)) + " s)");
  const double rate = rate_hz > 0.0 ? rate_hz : fastest_hz;
  if (rate <= 0.0)
    throw std::invalid_argument(
        "no rate to resample at: none of the signals has two distinct "
        "times; give the rate");
  const double period_us = 1e6 / rate;
  const double span_periods = static_cast<double>(end_us - begin_us) / period_us;
  const double max_points =
      static_cast<double>(kMaxResampledCells) / static_cast<double>(names.size() + 1);
  if (!(span_periods + 1.0 <= max_points))
    throw std::invalid_argument("resampling " + std::to_string(names.size()) + " signals over " +
                                std::to_string(static_cast<double>(end_us - begin_us) / 1e6) +
                                " s at " + std::to_string(rate) + " Hz makes more than " +
                                std::to_string(kMaxResampledCells) + " cells");
  const std::size_t points = static_cast<std::size_t>(std::floor(span_periods)) + 1;

  ResampledSignals out;
  out.rate_hz = rate;
  out.names = names;
  out.t_s.resize(points);
  const double t0_s = SecondsSince(file.start_time_us, begin_us);
  const double begin = static_cast<double>(begin_us);
  // Each time from its index, so that no rounding accumulates along a long grid.
  for (std::size_t i = 0; i < points; ++i) out.t_s[i] = t0_s + static_cast<double>(i) / rate;
  // A relative tolerance lets neighbours exactly max_gap + 1 periods apart through despite the
  // rounding of the period.
  const double widest = (max_gap + 1.0) * period_us * (1.0 + 1e-9);
  for (const Series& s : series) {
    std::vector<double> column(points);
    std::size_t gaps = 0;
    std::size_t hi = 0;  // the first sample later than the grid time; grid times only increase
    for (std::size_t i = 0; i < points; ++i) {
      const double t = begin + static_cast<double>(i) * period_us;
      while (hi < s.t_us.size() && static_cast<double>(s.t_us[hi]) <= t) ++hi;
      if (hi == 0) hi = 1;  // t at the first sample despite rounding: begin is a sample time
      const std::size_t lo = hi - 1;
      const double t_lo = static_cast<double>(s.t_us[lo]);
      if (t_lo == t || hi == s.t_us.size()) {
        column[i] = s.values[lo];  // a sample at t, or the last grid time rounded past the end
        continue;
      }
      const double t_hi = static_cast<double>(s.t_us[hi]);
      if (t_hi - t_lo > widest) {
        column[i] = std::numeric_limits<double>::quiet_NaN();
        ++gaps;
        continue;
      }
      column[i] = s.values[lo] + (s.values[hi] - s.values[lo]) * ((t - t_lo) / (t_hi - t_lo));
    }
    out.columns.push_back(std::move(column));
    out.out_of_order.push_back(s.out_of_order);
    out.gap_cells.push_back(gaps);
  }
  return out;
}

}  // namespace odonata::ulog
