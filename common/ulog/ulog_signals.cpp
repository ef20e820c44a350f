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

// Euler angles derived from a quaternion field "q" (float[4]).
enum class Derived { kNone, kRollRad, kPitchRad, kYawRad };

struct SignalRef {
  std::string name;
  std::size_t instance = 0;
  const FieldLayout* field = nullptr;
  std::size_t element = 0;
  Derived derived = Derived::kNone;
};

struct Catalogue {
  std::vector<TopicInstance> instances;
  std::vector<SignalRef> signals;
  std::unordered_map<std::string, std::size_t> by_name;
};

bool IsSignalField(const FieldLayout& f) {
  return f.type != BasicType::kChar && f.path != "timestamp";
}

bool IsQuaternion(const FieldLayout& f) {
  return f.path == "q" && f.is_array && f.count == 4 &&
         (f.type == BasicType::kFloat || f.type == BasicType::kDouble);
}

// Flags and enumerations: a state, held between samples.
timeseries::Interpolation InterpolationOf(const SignalRef& r) {
  if (r.derived != Derived::kNone) return timeseries::Interpolation::kLinear;
  const BasicType t = r.field->type;
  return t == BasicType::kBool || t == BasicType::kUint8 || t == BasicType::kInt8
             ? timeseries::Interpolation::kHold
             : timeseries::Interpolation::kLinear;
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
      if (!IsQuaternion(f)) continue;
      for (const auto& [suffix, kind] :
           {std::pair{".roll_rad", Derived::kRollRad}, std::pair{".pitch_rad", Derived::kPitchRad},
            std::pair{".yaw_rad", Derived::kYawRad}}) {
        std::string name = ti.prefix + suffix;
        if (c.by_name.emplace(name, c.signals.size()).second)
          c.signals.push_back(SignalRef{std::move(name), i, &f, 0, kind});
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

// The median step between a subscription's increasing timestamps (0 with fewer than two).
std::uint64_t MedianStepUs(const Subscription& s) {
  std::vector<std::uint64_t> dt;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (s.timestamps_us[i] > s.timestamps_us[i - 1])
      dt.push_back(s.timestamps_us[i] - s.timestamps_us[i - 1]);
  if (dt.empty()) return 0;
  std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2), dt.end());
  return dt[dt.size() / 2];
}

// Sample indices of one subscription kept in time order: a sample earlier than the last kept one
// is dropped. So is a lone leap ahead (a flipped byte in a timestamp: the sample jumps over 1000
// median steps ahead and the next one is back in sequence, or it is the last): kept, it would
// drop every later sample as out of order and stretch the signal's span to years.
std::vector<std::size_t> KeptSamples(const Subscription& s, std::size_t& dropped) {
  std::vector<std::size_t> kept;
  kept.reserve(s.size());
  const std::uint64_t leap = 1000 * MedianStepUs(s);
  const auto& t = s.timestamps_us;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!kept.empty() && t[i] < t[kept.back()]) {
      ++dropped;
      continue;
    }
    const bool leaps = !kept.empty() && leap > 0 && t[i] - t[kept.back()] > leap &&
                       (i + 1 == s.size() || (t[i + 1] < t[i] && t[i + 1] >= t[kept.back()]));
    if (leaps) {
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

// One Euler angle (Z-Y-X, radians) of the rotation q = [w, x, y, z].
double EulerAngle(Derived kind, double w, double x, double y, double z) {
  switch (kind) {
    case Derived::kRollRad:
      return std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
    case Derived::kPitchRad:
      return std::asin(std::clamp(2.0 * (w * y - z * x), -1.0, 1.0));
    default:
      return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
  }
}

// Adds whole turns so that no step between neighbours exceeds half a turn.
void Unwrap(std::vector<double>& angle_rad) {
  constexpr double kTurn = 2.0 * 3.14159265358979323846;
  double offset = 0.0;
  for (std::size_t i = 1; i < angle_rad.size(); ++i) {
    const double raw = angle_rad[i];
    const double step = raw + offset - angle_rad[i - 1];
    if (std::isfinite(step)) offset -= kTurn * std::round(step / kTurn);
    angle_rad[i] = raw + offset;
  }
}

Series SeriesOf(const Catalogue& c, const SignalRef& ref) {
  Series out;
  const auto timeline = Timeline(c.instances[ref.instance], out.out_of_order);
  out.t_us.reserve(timeline.size());
  out.values.reserve(timeline.size());
  for (const auto& [s, i] : timeline) {
    out.t_us.push_back(s->timestamps_us[i]);
    if (ref.derived == Derived::kNone) {
      out.values.push_back(s->Value(i, *ref.field, ref.element));
      continue;
    }
    const FieldLayout& q = *ref.field;
    out.values.push_back(EulerAngle(ref.derived, s->Value(i, q, 0), s->Value(i, q, 1),
                                    s->Value(i, q, 2), s->Value(i, q, 3)));
  }
  if (ref.derived == Derived::kRollRad || ref.derived == Derived::kYawRad) Unwrap(out.values);
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

// Where a signal of an older PX4 log lives in a current one (PX4 1.13 split actuator_controls;
// body rates left vehicle_attitude in 1.10): docs/guide/real-flights.md has the whole table.
std::string Px4RenameHint(const std::string& name) {
  const auto starts = [&name](const char* p) { return name.rfind(p, 0) == 0; };
  if (starts("vehicle_attitude.rollspeed") || starts("vehicle_attitude.pitchspeed") ||
      starts("vehicle_attitude.yawspeed"))
    return "current PX4 logs hold body rates in vehicle_angular_velocity.xyz[0], [1], [2] "
           "(roll, pitch, yaw; rad/s)";
  if (name == "vehicle_attitude.roll" || name == "vehicle_attitude.pitch" ||
      name == "vehicle_attitude.yaw")
    return "current PX4 logs hold the attitude as vehicle_attitude.q; its Euler angles are "
           "vehicle_attitude.roll_rad, pitch_rad, yaw_rad";
  if (starts("actuator_controls_0.control["))
    return "current PX4 logs hold the torque commands in vehicle_torque_setpoint.xyz[0..2], the "
           "thrust command in vehicle_thrust_setpoint.xyz[2] and motor outputs in "
           "actuator_motors.control[i]";
  return "";
}

const SignalRef& Lookup(const UlogFile& file, const Catalogue& c, const std::string& name) {
  if (const auto it = c.by_name.find(name); it != c.by_name.end()) return c.signals[it->second];
  const std::vector<std::string> near = cli::NearestNames(
      name, c.signals, [](const auto& s) -> const std::string& { return s.name; });
  const std::size_t shown = near.size();
  std::string message = "no signal '" + name + "' in " + file.source;
  if (const std::string hint = Px4RenameHint(name); !hint.empty()) message += " (" + hint + ")";
  const std::string prefix = name.substr(0, name.find('.'));
  for (const auto& ti : c.instances)
    if (ti.prefix == prefix && !ti.HasSamples())
      throw std::invalid_argument(message + ": topic '" + prefix +
                                  "' is subscribed but has no samples");
  if (shown == 0) throw std::invalid_argument(message + " (it has no numeric signals)");
  message += "; nearest: ";
  message += cli::JoinNames(near);
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
    out.push_back(SignalInfo{
        ref.name, s.topic, s.multi_id,
        ref.derived == Derived::kNone ? TypeName(ref.field->type) : std::string("derived"),
        InterpolationOf(ref), t.samples, t.out_of_order, t.median_hz, t.mean_hz});
  }
  return out;
}

SignalSamples Extract(const UlogFile& file, const std::string& name) {
  const Catalogue c = Catalog(file);
  const SignalRef& ref = Lookup(file, c, name);
  Series s = SeriesOf(c, ref);
  SignalSamples out;
  out.name = name;
  out.interpolation = InterpolationOf(ref);
  out.out_of_order = s.out_of_order;
  out.values = std::move(s.values);
  out.t_s.reserve(s.t_us.size());
  for (const std::uint64_t t : s.t_us) out.t_s.push_back(SecondsSince(file.start_time_us, t));
  return out;
}

ResampledSignals Resample(const UlogFile& file, const std::vector<std::string>& names,
                          const timeseries::GridOptions& grid,
                          const std::vector<std::string>& held) {
  if (names.empty()) throw std::invalid_argument("resampling needs at least one signal");
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (names[i] == names[j])
        throw std::invalid_argument("signal '" + names[i] + "' is asked for twice");
  const Catalogue c = Catalog(file);
  std::vector<timeseries::TimedSignal> timed;
  ResampledSignals out;
  for (const auto& name : names) {
    const SignalRef& ref = Lookup(file, c, name);
    Series s = SeriesOf(c, ref);
    timeseries::TimedSignal t;
    t.name = name;
    t.interpolation = std::find(held.begin(), held.end(), name) != held.end()
                          ? timeseries::Interpolation::kHold
                          : InterpolationOf(ref);
    t.t_s.reserve(s.t_us.size());
    for (const std::uint64_t us : s.t_us) t.t_s.push_back(SecondsSince(file.start_time_us, us));
    t.values = std::move(s.values);
    out.out_of_order.push_back(s.out_of_order);
    out.interpolation.push_back(t.interpolation);
    timed.push_back(std::move(t));
  }
  timeseries::GridOptions o = grid;
  o.max_cells = kMaxResampledCells;
  timeseries::UniformGrid g = timeseries::Resample(timed, o);
  out.rate_hz = g.rate_hz;
  out.rate_chosen = g.rate_chosen;
  out.t_s = std::move(g.t_s);
  out.names = names;
  out.columns = std::move(g.columns);
  for (const auto& s : g.signals) {
    out.gap_cells.push_back(s.gap_cells);
    out.median_rate_hz.push_back(s.median_rate_hz);
  }
  return out;
}

ResampledSignals Resample(const UlogFile& file, const std::vector<std::string>& names,
                          double rate_hz, int max_gap) {
  timeseries::GridOptions o;
  o.rate_hz = rate_hz;
  o.max_gap = max_gap;
  return Resample(file, names, o);
}

}  // namespace odonata::ulog
