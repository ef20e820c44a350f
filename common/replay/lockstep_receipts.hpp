#pragma once
// Which consumers hold which replayed sample: the receipts (ack_t on the signals_ack channel) of
// the identifiers and loggers a lockstep replay waits for, so it sends sample k+1 only when every
// one of them holds sample k, and nothing is lost however slowly one of them learns.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace odonata::replay {

class LockstepReceipts {
 public:
  /// Waits for these instances (more may join with Await before the first sample).
  explicit LockstepReceipts(std::vector<std::string> consumers = {});
  void Await(const std::string& instance);
  const std::vector<std::string>& consumers() const { return consumers_; }

  /// `instance` holds samples up to `held`. Receipts of instances not awaited, and ones beyond
  /// the newest sample sent (`sent`: a receipt left over from an earlier run), change nothing.
  void OnReceipt(const std::string& instance, int64_t held, int64_t sent);
  /// Every awaited consumer holds sample `seq` (true when none is awaited).
  bool Confirmed(int64_t seq) const;
  /// The awaited consumers that do not hold `seq` yet.
  std::vector<std::string> Missing(int64_t seq) const;
  /// A new replay run starts at seq 0: the receipts of the last one say nothing about it.
  void Restart();

 private:
  std::vector<std::string> consumers_;
  std::map<std::string, int64_t> held_;  // by instance: newest sample held, −1 none
};

}  // namespace odonata::replay
