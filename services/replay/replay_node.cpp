#include "replay_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "odonata/ack_t.hpp"
#include "odonata/heartbeat_t.hpp"
#include "odonata/signals_t.hpp"

namespace odonata::replay {
namespace {
using Clock = std::chrono::steady_clock;

// "a, b" for the instances.
std::string Names(const std::vector<std::string>& instances) {
  std::string names;
  for (const auto& c : instances) names += (names.empty() ? "" : ", ") + c;
  return names;
}

std::chrono::microseconds Micros(double seconds) {
  return std::chrono::microseconds(static_cast<int64_t>(seconds * 1e6));
}
}  // namespace

ReplayNode::ReplayNode(bus::BusNode& bus, FlightRows flight, ReplayOptions options)
    : bus_(bus),
      flight_(std::move(flight)),
      options_(std::move(options)),
      receipts_(options_.wait_for) {
  // On a keyless bus a forged "refitting" heartbeat cannot be told from a real one: it may
  // stall the replay for under a minute, not ten (docs/lcm.md §10).
  patience_.set_max_timeouts(pipeline::RefitWaitTimeouts(
      options_.refit_wait_s, !bus_.options().key_path.empty(), options_.timeout_ms));
  if (options_.lockstep) {
    bus_.Subscribe<odonata::ack_t>(bus_.channels().signals_ack, [this](const odonata::ack_t& a) {
      receipts_.OnReceipt(a.instance, a.state_seq, newest_seq_);
      if (awaited_ < 0 || !receipts_.Confirmed(awaited_)) return;
      awaited_ = -1;
      ++generation_;  // the pending resend is for a sample now held
      SendLockstep(static_cast<std::size_t>(newest_seq_) + 1);
    });
    // Consumers announce themselves by heartbeat: each identifier and logger heard before the
    // first sample is waited for, so none of them misses one; an awaited one that says it is
    // landing a scheduled refit is waited for with patience, not resends (as odonata-signal).
    bus_.Subscribe<odonata::heartbeat_t>(
        bus_.channels().heartbeat, [this](const odonata::heartbeat_t& h) {
          if (h.service != "odonata-identifier" && h.service != "odonata-logger") return;
          if (!started_ && options_.discover_s > 0) receipts_.Await(h.instance);
          const auto& awaited = receipts_.consumers();
          if (std::find(awaited.begin(), awaited.end(), h.instance) != awaited.end())
            patience_.SetBusy(h.instance, h.state == "refitting");
        });
  }
  bus_.OnShutdown([this] {
    if (!finished_) {
      end_ = Clock::now();
      bus_.SetExitCode(kExitInterrupted);
      std::fprintf(stderr, "odonata-replay: interrupted after %lld of %zu samples\n",
                   static_cast<long long>(sent_), flight_.rows.size());
    }
  });
  bus_.SetState("starting");
  if (options_.lockstep && options_.discover_s > 0)
    bus_.After(Micros(options_.discover_s), [this] { Begin(); });
  else
    bus_.After(std::chrono::microseconds(0), [this] { Begin(); });
}

void ReplayNode::Begin() {
  started_ = true;
  start_ = last_progress_ = Clock::now();
  pacer_ = pipeline::RealtimePacer(start_, options_.speed);
  bus_.SetState("replaying");
  if (options_.lockstep) {
    const std::string who = Names(receipts_.consumers());
    std::fprintf(
        stderr, "odonata-replay: %zu samples of %s in lockstep with %s\n", flight_.rows.size(),
        flight_.source.c_str(),
        who.empty() ? "nobody (no identifier or logger heard; --wait-for names one)" : who.c_str());
    SendLockstep(0);
  } else {
    std::fprintf(stderr, "odonata-replay: %zu samples of %s at %g× the flight's pace (%.1f s)\n",
                 flight_.rows.size(), flight_.source.c_str(), options_.speed,
                 flight_.times_s.back() / options_.speed);
    SendPaced(0);
  }
}

std::size_t ReplayNode::NextComplete(std::size_t row) {
  while (row < flight_.rows.size() && !flight_.Complete(row)) {
    ++skipped_;
    ++row;
  }
  return row;
}

void ReplayNode::Publish(std::size_t row) {
  odonata::signals_t m;
  m.utime = bus::NowUtime();
  m.seq = static_cast<int64_t>(row);  // the sample index: a skipped row is a gap
  m.source = options_.source;
  m.num_signals = static_cast<int32_t>(flight_.names.size());
  m.names = flight_.names;
  m.values = flight_.rows[row];
  bus_.Publish(bus_.channels().signals, m);
  newest_seq_ = m.seq;
}

void ReplayNode::SendPaced(std::size_t row) {
  row = NextComplete(row);
  if (row >= flight_.rows.size()) return Finish(0);
  Publish(row);
  ++sent_;
  Progress(row);
  const std::size_t next = row + 1;
  if (next >= flight_.rows.size()) return Finish(0);
  // Each sample at its own time from the start, so the pace does not drift with the loop's
  // latency.
  const auto wait =
      pipeline::RealtimePacer::Wait(pacer_.DueAt(flight_.times_s[next]), Clock::now());
  bus_.After(std::chrono::duration_cast<std::chrono::microseconds>(wait),
             [this, next] { SendPaced(next); });
}

void ReplayNode::SendLockstep(std::size_t row) {
  row = NextComplete(row);
  if (row >= flight_.rows.size()) return Finish(0);
  Publish(row);
  ++sent_;
  Progress(row);
  awaited_ = static_cast<int64_t>(row);
  resends_of_awaited_ = 0;
  patience_.Reset();
  if (receipts_.Confirmed(awaited_)) {  // nobody to wait for
    awaited_ = -1;
    bus_.After(std::chrono::microseconds(0), [this, row] { SendLockstep(row + 1); });
    return;
  }
  ArmResend(row, generation_);
}

void ReplayNode::ArmResend(std::size_t row, int64_t generation) {
  bus_.After(std::chrono::milliseconds(options_.timeout_ms), [this, row, generation] {
    if (generation != generation_ || finished_) return;  // held meanwhile
    switch (patience_.OnTimeout(receipts_.Missing(static_cast<int64_t>(row)))) {
      case pipeline::RefitPatience::Verdict::kWait:
        if (const std::string notice = patience_.Notice(
                options_.timeout_ms, Names(receipts_.Missing(static_cast<int64_t>(row))),
                !bus_.options().key_path.empty());
            !notice.empty())
          std::fprintf(stderr, "odonata-replay: %s\n", notice.c_str());
        return ArmResend(row, generation);
      case pipeline::RefitPatience::Verdict::kSpent:
        std::fprintf(stderr,
                     "odonata-replay: error: %s has been landing a scheduled refit for %.0f s at "
                     "sample %zu, longer than --refit-wait\n",
                     Names(receipts_.Missing(static_cast<int64_t>(row))).c_str(),
                     patience_.in_a_row() * options_.timeout_ms / 1000.0, row);
        return Finish(kExitConsumerLost);
      case pipeline::RefitPatience::Verdict::kNotBusy:
        break;
    }
    if (resends_of_awaited_ >= options_.max_resends) {
      std::fprintf(stderr,
                   "odonata-replay: error: %s did not acknowledge sample %zu after %d resends "
                   "(%d ms apart): is it running, with source \"signals\", on this bus, channel "
                   "and key? (--wait-for names the consumers to wait for)\n",
                   Names(receipts_.Missing(static_cast<int64_t>(row))).c_str(), row,
                   resends_of_awaited_, options_.timeout_ms);
      return Finish(kExitConsumerLost);
    }
    ++resends_of_awaited_;
    ++resends_;
    Publish(row);  // the same sample again: a consumer that holds it answers again
    ArmResend(row, generation);
  });
}

void ReplayNode::Progress(std::size_t row) {
  if (options_.progress_s <= 0) return;
  const auto now = Clock::now();
  if (now - last_progress_ < Micros(options_.progress_s)) return;
  last_progress_ = now;
  std::fprintf(stderr, "odonata-replay: sample %zu of %zu (%.0f %%)\n", row + 1,
               flight_.rows.size(), 100.0 * double(row + 1) / double(flight_.rows.size()));
}

void ReplayNode::Finish(int exit_code) {
  if (finished_) return;
  finished_ = true;
  end_ = Clock::now();
  bus_.SetState(exit_code == 0 ? "finished" : "error");
  bus_.Stop(exit_code);
}

nlohmann::json ReplayNode::Summary() const {
  const double seconds =
      started_ ? std::chrono::duration<double>((finished_ ? end_ : Clock::now()) - start_).count()
               : 0.0;
  nlohmann::json j = {{"file", flight_.source},
                      {"signals", flight_.names},
                      {"rows", flight_.rows.size()},
                      {"samples_sent", sent_},
                      {"rows_skipped", skipped_},
                      {"flight_s", flight_.times_s.empty() ? 0.0 : flight_.times_s.back()},
                      {"seconds", seconds},
                      {"mode", options_.lockstep ? "lockstep" : "paced"},
                      {"finished", finished_}};
  if (options_.lockstep) {
    j["consumers"] = receipts_.consumers();
    j["resends"] = resends_;
    j["refit_timeouts"] = patience_.total();
  } else {
    j["speed"] = options_.speed;
  }
  return j;
}

std::string ReplayNode::SummaryLine() const {
  const double seconds = Summary()["seconds"].get<double>();
  char mode[96];
  if (options_.lockstep)
    std::snprintf(mode, sizeof mode, "lockstep, %lld resends", static_cast<long long>(resends_));
  else
    std::snprintf(mode, sizeof mode, "at %g× the flight's pace", options_.speed);
  char line[512];
  std::snprintf(line, sizeof line,
                "sent %lld of %zu samples of %s (%lld rows with a gap not sent) in %.1f s, %s",
                static_cast<long long>(sent_), flight_.rows.size(), flight_.source.c_str(),
                static_cast<long long>(skipped_), seconds, mode);
  return line;
}

}  // namespace odonata::replay
