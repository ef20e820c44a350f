#include "mavlink/bridge_core.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

#include "cli/parse_command_line.hpp"

namespace odonata::mavlink {
namespace {

constexpr double kBridgeNaN = std::numeric_limits<double>::quiet_NaN();
/// Senders named per message in other_senders (a hostile stream must not grow it unbounded).
constexpr std::size_t kMaxOtherSenders = 16;
/// Times kept per field for choosing the rate (2 s at 32 kHz).
constexpr std::size_t kMaxRateWindowSamples = std::size_t{1} << 16;

const char* const kBridgeSelectorForms =
    "write MESSAGE.field, MESSAGE.field[i] or MESSAGE@sysid:compid.field "
    "(ATTITUDE.pitchspeed, ACTUATOR_OUTPUT_STATUS.actuator[1], ATTITUDE@1:1.pitch)";

// The name of `names` nearest to `word` by edit distance (the first on a tie); empty for none.
std::string BridgeNearestName(const std::string& word, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const std::string& n : names) {
    const std::size_t d = cli::EditDistance(word, n);
    if (d < best_d) {
      best_d = d;
      best = n;
    }
  }
  return best;
}

// A decimal number 0..255, or nullopt.
std::optional<std::uint8_t> BridgeSenderByte(const std::string& text) {
  if (text.empty() || text.size() > 3) return std::nullopt;
  unsigned value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    value = value * 10 + static_cast<unsigned>(c - '0');
  }
  if (value > 255) return std::nullopt;
  return static_cast<std::uint8_t>(value);
}

std::string BridgeHz(double hz) {
  char s[32];
  std::snprintf(s, sizeof s, "%.6g Hz", hz);
  return s;
}

// "ATTITUDE@1:1.pitch" or "ATTITUDE.pitch": one key per distinct field.
std::string BridgeCanonical(const FieldSelector& s) {
  std::string key = s.message;
  if (s.sysid && s.compid) key += "@" + std::to_string(*s.sysid) + ":" + std::to_string(*s.compid);
  return key + "." + s.field;
}

}  // namespace

bool GridSample::gap() const {
  return std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); });
}

FieldSelector ParseFieldSelector(const std::string& text) {
  const std::size_t dot = text.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size())
    throw std::invalid_argument("field '" + text + "': " + kBridgeSelectorForms);
  FieldSelector sel;
  sel.name = text;
  sel.field = text.substr(dot + 1);
  std::string head = text.substr(0, dot);
  const std::size_t at = head.find('@');
  if (at != std::string::npos) {
    const std::string sender = head.substr(at + 1);
    head = head.substr(0, at);
    const std::size_t colon = sender.find(':');
    const std::optional<std::uint8_t> sysid =
        colon == std::string::npos ? std::nullopt : BridgeSenderByte(sender.substr(0, colon));
    const std::optional<std::uint8_t> compid =
        colon == std::string::npos ? std::nullopt : BridgeSenderByte(sender.substr(colon + 1));
    if (!sysid || !compid)
      throw std::invalid_argument(
          "field '" + text + "': the sender '" + sender +
          "' must be sysid:compid, two numbers 0..255 (ATTITUDE@1:1.pitch)");
    sel.sysid = sysid;
    sel.compid = compid;
  }
  sel.message = head;
  const MessageDef* m = FindByName(head);
  if (m == nullptr) {
    std::vector<std::string> names;
    for (const MessageDef& k : KnownMessages()) names.push_back(k.name);
    throw std::invalid_argument("field '" + text + "': no MAVLink message '" + head +
                                "' is known; nearest: " + BridgeNearestName(head, names));
  }
  if (FindField(*m, sel.field)) return sel;
  std::vector<std::string> values;
  for (const FieldDef& f : m->fields) {
    if (sel.field == f.name && f.type == FieldType::kChar)
      throw std::invalid_argument("field '" + text + "': " + m->name + "." + f.name +
                                  " is text, not a number");
    if (sel.field == f.name && f.array_length != 0)
      throw std::invalid_argument("field '" + text + "': " + m->name + "." + f.name +
                                  " is an array of " + std::to_string(f.count()) +
                                  "; name one element, " + f.name + "[0] to " + f.name + "[" +
                                  std::to_string(f.count() - 1) + "]");
    if (f.type == FieldType::kChar) continue;
    if (f.array_length == 0) {
      values.push_back(f.name);
    } else {
      for (std::size_t e = 0; e < f.count(); ++e)
        values.push_back(f.name + "[" + std::to_string(e) + "]");
    }
  }
  throw std::invalid_argument("field '" + text + "': " + m->name + " has no value '" + sel.field +
                              "'; nearest: " + m->name + "." +
                              BridgeNearestName(sel.field, values));
}

BridgeCore::BridgeCore(BridgeOptions options)
    : options_(std::move(options)),
      decoder_(options_.signature_check),
      t0_s_(std::numeric_limits<double>::quiet_NaN()) {
  if (options_.fields.empty()) throw std::invalid_argument("the bridge needs at least one field");
  if (!std::isfinite(options_.rate_hz) || options_.rate_hz < 0.0)
    throw std::invalid_argument(
        "the grid's rate must be a finite number of Hz >= 0 (0: chosen), not " +
        std::to_string(options_.rate_hz));
  if (options_.max_gap < 0)
    throw std::invalid_argument("max_gap must be >= 0, not " + std::to_string(options_.max_gap));
  if (!(options_.silence_s > 0.0) || !std::isfinite(options_.silence_s))
    throw std::invalid_argument("silence_s must be a finite number of seconds > 0, not " +
                                std::to_string(options_.silence_s));
  std::vector<std::string> keys;
  for (const std::string& text : options_.fields) {
    NamedField f;
    f.selector = ParseFieldSelector(text);
    const std::string key = BridgeCanonical(f.selector);
    if (std::find(keys.begin(), keys.end(), key) != keys.end())
      throw std::invalid_argument("field '" + text + "' is named twice");
    keys.push_back(key);
    f.message = FindByName(f.selector.message);
    f.ref = *FindField(*f.message, f.selector.field);  // ParseFieldSelector checked both
    f.interpolation = f.ref.type == FieldType::kUint8 ? timeseries::Interpolation::kHold
                                                      : timeseries::Interpolation::kLinear;
    if (f.selector.sysid && f.selector.compid)
      f.sender = SenderKey(*f.selector.sysid, *f.selector.compid);
    fields_.push_back(std::move(f));
  }
  if (options_.rate_hz > 0.0) {
    SetRate(options_.rate_hz);
    rate_note_ = "the grid's rate, " + BridgeHz(rate_hz_) + ", was given";
  }
}

void BridgeCore::SetRate(double rate_hz) {
  // Timeseries::Resample's arithmetic, operation for operation.
  rate_hz_ = rate_hz;
  period_s_ = 1.0 / rate_hz_;
  eps_s_ = 1e-9 * period_s_;
  reach_s_ = (options_.max_gap + 1.0) * period_s_ * (1.0 + 1e-9);
}

void BridgeCore::Feed(std::string_view bytes, double arrival_s) {
  if (!first_arrival_s_) first_arrival_s_ = arrival_s;
  decoder_.Feed(bytes, [this, arrival_s](const Frame& frame) { OnFrame(frame, arrival_s); });
}

void BridgeCore::EndOfDatagram(double arrival_s) {
  if (!first_arrival_s_) first_arrival_s_ = arrival_s;
  decoder_.Finish([this, arrival_s](const Frame& frame) { OnFrame(frame, arrival_s); });
}

void BridgeCore::OnFrame(const Frame& frame, double arrival_s) {
  if (frame.message == nullptr) return;
  if (!frame.is_signed() && options_.unsigned_frames == UnsignedFrames::kRefuse) {
    ++unsigned_refused_;
    return;
  }
  if (options_.on_frame) options_.on_frame(frame);
  const std::uint16_t key = SenderKey(frame.sysid, frame.compid);
  bool named = false;
  bool taken = false;
  bool sampled = false;
  for (NamedField& f : fields_) {
    if (f.message != frame.message) continue;
    named = true;
    if (!f.sender) f.sender = key;  // a plain name: the first sender heard
    if (*f.sender != key) continue;
    taken = true;
    ++f.frames;
    f.last_heard_s = arrival_s;
    const double value = Field(frame, f.ref);
    if (!std::isfinite(value) || !std::isfinite(arrival_s)) continue;  // no sample
    if (f.accepted > 0 && arrival_s < f.last_s) {
      ++f.out_of_order;
      continue;
    }
    if (f.accepted == 0) f.first_s = arrival_s;
    f.last_s = arrival_s;
    ++f.accepted;
    f.samples.push_back(Sample{arrival_s, value});
    if (f.samples.size() > kMaxBufferedSamples) {
      f.samples.pop_front();
      ++f.overflow_dropped;
    }
    if (rate_hz_ == 0.0 && arrival_s - f.first_s <= kRateWindowS &&
        f.rate_window_t_s.size() < kMaxRateWindowSamples)
      f.rate_window_t_s.push_back(arrival_s);
    sampled = true;
  }
  if (named && !taken) {
    ++other_sender_;
    auto& senders = other_senders_[frame.message->name];
    if (senders.size() < kMaxOtherSenders)
      senders.insert(std::to_string(frame.sysid) + ":" + std::to_string(frame.compid));
  }
  if (sampled) Advance();
}

void BridgeCore::ChooseRate() {
  if (rate_refused_) return;
  for (const NamedField& f : fields_)
    if (f.accepted == 0 || f.last_s - f.first_s <= kRateWindowS) return;  // still listening
  const bool any_linear = std::any_of(fields_.begin(), fields_.end(), [](const NamedField& f) {
    return f.interpolation == timeseries::Interpolation::kLinear;
  });
  double slowest_hz = std::numeric_limits<double>::infinity();
  const NamedField* slowest = nullptr;
  for (const NamedField& f : fields_) {
    if (any_linear && f.interpolation != timeseries::Interpolation::kLinear) continue;
    const double hz = timeseries::MedianRateHz(f.rate_window_t_s);
    if (hz > 0.0 && hz < slowest_hz) {
      slowest_hz = hz;
      slowest = &f;
    }
  }
  if (slowest == nullptr) {
    rate_refused_ = true;
    rate_note_ = "no rate: no field has two distinct times in its first " +
                 std::to_string(static_cast<int>(kRateWindowS)) + " s; give the rate";
    return;
  }
  SetRate(slowest_hz);
  rate_note_ = "the grid's rate, " + BridgeHz(rate_hz_) + ", is " + slowest->selector.name +
               "'s median rate over its first " + std::to_string(static_cast<int>(kRateWindowS)) +
               " s: the slowest named field's; give the rate to choose another";
  for (NamedField& f : fields_) {
    f.rate_window_t_s.clear();
    f.rate_window_t_s.shrink_to_fit();
  }
}

void BridgeCore::Advance() {
  if (std::isnan(t0_s_)) {
    double latest_first = -std::numeric_limits<double>::infinity();
    bool all_heard = true;
    for (const NamedField& f : fields_) {
      if (f.accepted == 0) {
        all_heard = false;
      } else {
        latest_first = std::max(latest_first, f.first_s);
      }
    }
    if (!all_heard) {
      Prune(latest_first);  // t0 will be at or after it
      return;
    }
    t0_s_ = latest_first;
  }
  if (rate_hz_ == 0.0) {
    ChooseRate();
    if (rate_hz_ == 0.0) {
      Prune(t0_s_);
      return;
    }
  }
  for (;;) {
    const double t_s = t0_s_ + static_cast<double>(next_k_) / rate_hz_;
    for (const NamedField& f : fields_) {
      if (f.samples.empty() || !(f.samples.back().t_s > t_s + eps_s_)) {
        Prune(t_s);
        return;
      }
    }
    GridSample s;
    s.k = next_k_;
    s.t_s = t_s;
    s.values.reserve(fields_.size());
    for (const NamedField& f : fields_) s.values.push_back(ValueAt(f, t_s));
    if (s.gap()) ++gap_samples_;
    ++grid_samples_;
    ready_.push_back(std::move(s));
    ++next_k_;
  }
}

void BridgeCore::Prune(double t_s) {
  // Keep the last sample at or before t_s (ValueAt's j for any later grid time is at or after
  // it) and everything after.
  for (NamedField& f : fields_)
    while (f.samples.size() >= 2 && f.samples[1].t_s <= t_s) f.samples.pop_front();
}

double BridgeCore::ValueAt(const NamedField& f, double t_s) const {
  // timeseries::Resample's Interpolated and Held, on the kept samples.
  const std::deque<Sample>& s = f.samples;
  std::size_t j = 0;
  while (j + 1 < s.size() && s[j + 1].t_s <= t_s + eps_s_) ++j;
  if (s[j].t_s > t_s + eps_s_) return kBridgeNaN;  // before its first kept sample
  if (f.interpolation == timeseries::Interpolation::kHold) return s[j].value;
  if (std::abs(s[j].t_s - t_s) <= eps_s_) return s[j].value;
  if (j + 1 >= s.size()) return kBridgeNaN;  // not reached: the sample is complete
  const double span = s[j + 1].t_s - s[j].t_s;
  if (span > reach_s_) return kBridgeNaN;
  return s[j].value + (s[j + 1].value - s[j].value) * ((t_s - s[j].t_s) / span);
}

std::vector<GridSample> BridgeCore::TakeSamples() {
  std::vector<GridSample> out;
  out.swap(ready_);
  return out;
}

std::vector<std::string> BridgeCore::Silent(double now_s) const {
  std::vector<std::string> silent;
  if (!first_arrival_s_) return silent;
  for (const NamedField& f : fields_) {
    const double since = f.frames == 0 ? *first_arrival_s_ : f.last_heard_s;
    if (now_s - since > options_.silence_s) silent.push_back(f.selector.name);
  }
  return silent;
}

std::size_t BridgeCore::bridge_dropped() const {
  std::size_t n = other_sender_ + unsigned_refused_;
  for (const NamedField& f : fields_) n += f.out_of_order + f.overflow_dropped;
  return n;
}

std::string BridgeCore::rate_note() const {
  if (rate_hz_ > 0.0 || rate_refused_) return rate_note_;
  return "the grid's rate is chosen once every named field has " +
         std::to_string(static_cast<int>(kRateWindowS)) + " s of samples";
}

nlohmann::json BridgeCore::Summary() const {
  const DecoderCounters& c = decoder_.counters();
  nlohmann::json unknown = nlohmann::json::object();
  for (const auto& [id, n] : c.unknown_ids) unknown[std::to_string(id)] = n;
  nlohmann::json j;
  j["frames"] = {{"ok", c.frames_ok},
                 {"v1", c.v1_frames},
                 {"signed", c.signed_frames},
                 {"truncated", c.truncated},
                 {"bad_crc", c.bad_crc},
                 {"bad_signature", c.bad_signature},
                 {"unknown_message", c.unknown_message},
                 {"unknown_ids", unknown},
                 {"incompatible", c.incompatible},
                 {"cut", c.cut},
                 {"dropped", c.dropped()},
                 {"bytes_skipped", c.bytes_skipped},
                 {"sequence_lost", decoder_.sequences().lost()},
                 {"other_sender", other_sender_},
                 {"unsigned_refused", unsigned_refused_},
                 {"other_senders", other_senders_}};
  j["grid"] = {{"rate_hz", rate_hz_},
               {"rate_note", rate_note()},
               {"t0_s", std::isnan(t0_s_) ? nlohmann::json() : nlohmann::json(t0_s_)},
               {"max_gap", options_.max_gap},
               {"samples", grid_samples_},
               {"gap_samples", gap_samples_}};
  nlohmann::json fields = nlohmann::json::array();
  for (const NamedField& f : fields_) {
    nlohmann::json x;
    x["name"] = f.selector.name;
    x["held"] = f.interpolation == timeseries::Interpolation::kHold;
    x["sender"] = f.sender ? nlohmann::json(std::to_string(*f.sender >> 8) + ":" +
                                            std::to_string(*f.sender & 0xFF))
                           : nlohmann::json();
    x["frames"] = f.frames;
    x["samples"] = f.accepted;
    x["out_of_order"] = f.out_of_order;
    x["overflow_dropped"] = f.overflow_dropped;
    x["last_heard_s"] = f.frames > 0 ? nlohmann::json(f.last_heard_s) : nlohmann::json();
    fields.push_back(std::move(x));
  }
  j["fields"] = std::move(fields);
  return j;
}

}  // namespace odonata::mavlink
