#include "bus/wire_bounds.hpp"

namespace odonata::bus {
namespace {

// A read-only cursor over LCM's wire format (big-endian; a string is an int32 length that counts
// its NUL, then the bytes). Every read fails once the buffer is exhausted, so a walker can chain
// reads and test ok() at the end.
class WireCursor {
 public:
  WireCursor(const void* data, int64_t size)
      : data_(static_cast<const uint8_t*>(data)), size_(data ? size : -1) {}

  bool ok() const { return ok_; }

  void Skip(int64_t bytes) {
    if (!ok_ || bytes < 0 || bytes > size_ - pos_) {
      ok_ = false;
      return;
    }
    pos_ += bytes;
  }

  // Reads an int32 used as an array count: negative counts (decode() would resize to ~2^64) and
  // counts larger than the whole message (no element takes less than a byte, but an array of
  // empty rows takes none, so the remaining bytes alone are no bound) are rejected.
  int64_t Count() {
    const int64_t n = Int32();
    if (n < 0 || n > size_) ok_ = false;
    return ok_ ? n : 0;
  }

  // decode() assigns length − 1 characters: a length of 0 would ask for 2^64 − 1.
  void String() {
    const int64_t length = Count();
    if (length < 1) ok_ = false;
    Skip(length);
  }

  void Strings(int64_t n) {
    for (int64_t i = 0; i < n && ok_; ++i) String();
  }

  // `n` elements of `bytes` each, with the product checked against the remaining bytes.
  void Array(int64_t n, int64_t bytes) {
    if (ok_ && bytes > 0 && n > (size_ - pos_) / bytes) ok_ = false;
    Skip(n * bytes);
  }

 private:
  int64_t Int32() {
    if (!ok_ || size_ - pos_ < 4) {
      ok_ = false;
      return 0;
    }
    const uint32_t v = (uint32_t{data_[pos_]} << 24) | (uint32_t{data_[pos_ + 1]} << 16) |
                       (uint32_t{data_[pos_ + 2]} << 8) | uint32_t{data_[pos_ + 3]};
    pos_ += 4;
    return static_cast<int32_t>(v);
  }

  const uint8_t* data_;
  int64_t size_;
  int64_t pos_ = 0;
  bool ok_ = size_ >= 0;
};

constexpr int64_t kFingerprint = 8, kI8 = 1, kI32 = 4, kI64 = 8, kF64 = 8;

void FuzzyRules(WireCursor& w) {
  w.String();  // output_name
  const int64_t rules = w.Count(), inputs = w.Count();
  w.Array(rules, inputs * kF64);  // centres
  w.Array(rules, inputs * kF64);  // sigmas
  w.Array(rules, kF64);           // output_widths
  w.String();                     // consequent
  const int64_t coefficients = w.Count();
  w.Array(rules, coefficients * kF64);
  const int64_t covariance = w.Count();
  w.Array(rules, covariance * kF64);
  w.Skip(kF64 + kI32 + 4 * kF64);  // entropy_threshold, max_rules, kappa … sigma_max
  w.String();                      // entropy_measure
  w.Skip(8 * kF64);                // rates, NLMS and RLS settings
  w.Skip(kF64 + kI32 + 2 * kI64);  // prune_utility, prune_min_age, clock, pruned
  w.Array(rules, kF64);            // utility_sums
  w.Array(rules, kI64);            // born
}

}  // namespace

bool CountsFit(const odonata::wing_command_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  w.Skip(kFingerprint + 2 * kI64 + kF64 + 24 * kF64);
  const int64_t n = w.Count();
  w.Strings(n);
  w.Array(n, kF64);
  w.String();  // source
  return w.ok();
}

bool CountsFit(const odonata::plant_state_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  w.Skip(kFingerprint + 3 * kI64 + kF64 + 20 * kF64 + kI8);
  return w.ok();
}

bool CountsFit(const odonata::beat_state_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  // utime, seq, command_seq; t_s, window_s, 3 × 3 means, 2 forces, 24 applied commands,
  // 4 channels; attitude_hold. No arrays of variable length.
  w.Skip(kFingerprint + 3 * kI64 + (2 + 9 + 2 + 24 + 4) * kF64 + kI8);
  return w.ok();
}

bool CountsFit(const odonata::prediction_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  w.Skip(kFingerprint + 3 * kI64);
  const int64_t n = w.Count();
  w.Strings(n);
  w.Array(n, 4 * kF64 + kI32 + kF64);  // measured, predicted, free_run, next, rules, max_entropy
  w.Skip(kI8);
  return w.ok();
}

bool CountsFit(const odonata::accuracy_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  w.Skip(kFingerprint + 3 * kI64 + kI32 + kI64);
  const int64_t n = w.Count();
  w.Strings(n);
  w.Array(n, 12 * kF64 + kI32);  // FIT, VAF, RMSE × window/total × one-step/free-run; rules
  w.Skip(kI64);
  return w.ok();
}

bool CountsFit(const odonata::model_snapshot_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  w.Skip(kFingerprint + 3 * kI64 + kI8);  // utime, seq, samples_learned, learning
  w.String();                             // instance
  w.Skip(3 * kI32);                       // lags, delay
  const int64_t outputs = w.Count();
  w.Strings(outputs);
  w.Strings(w.Count());  // inputs
  const int64_t regressors = w.Count();
  w.Array(regressors, 2 * kF64);
  w.Array(outputs, 2 * kF64);
  for (int64_t i = 0; i < outputs && w.ok(); ++i) FuzzyRules(w);
  return w.ok();
}

bool CountsFit(const odonata::heartbeat_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  w.Skip(kFingerprint + 2 * kI64);
  w.Strings(3);  // service, instance, host
  w.Skip(kI32);
  w.String();        // state
  w.Skip(7 * kI64);  // messages_in … repeated
  w.String();        // last_error
  return w.ok();
}

bool CountsFit(const odonata::control_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  w.Skip(kFingerprint + 2 * kI64);
  w.String();  // sender
  w.String();  // target
  w.Skip(kI8 + kF64);
  w.String();  // path
  return w.ok();
}

bool CountsFit(const odonata::ack_t*, const void* data, int64_t size) {
  WireCursor w(data, size);
  w.Skip(kFingerprint + 2 * kI64);
  w.Strings(2);  // service, instance
  w.Skip(kI64);
  return w.ok();
}

}  // namespace odonata::bus
