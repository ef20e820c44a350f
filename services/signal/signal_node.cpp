#include "signal_node.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <stdexcept>

#include "bus/safe_decode.hpp"
#include "messages/wing_command_message.hpp"

namespace odonata::signal_service {
namespace {
// Terminal progress refresh period.
constexpr std::chrono::milliseconds kProgressPeriodMs{100};
}  // namespace

SignalNode::SignalNode(bus::BusNode& bus, pipeline::CommandSchedule schedule, SignalOptions options)
    : bus_(bus),
      schedule_(std::move(schedule)),
      options_(std::move(options)),
      // A restarted plant repeats its state 0 every 200 ms (plant_node.hpp): wait at least
      // 600 ms before dropping the suspicion a lone state 0 raises.
      sequencer_(static_cast<int64_t>(schedule_.size()), options_.reset_plant, options_.max_resends,
                 std::max(3, (600 + std::max(options_.timeout_ms, 1) - 1) /
                                 std::max(options_.timeout_ms, 1)),
                 options_.window),
      timer_(bus.io()),
      release_(bus.io()) {
  if (!(options_.rate_hz > 0) || options_.timeout_ms <= 0) {
    throw std::invalid_argument("rate_hz and timeout_ms must be positive");
  }
  // On a keyless bus a forged "refitting" heartbeat cannot be told from a real one: it may
  // stall the run for under a minute, not ten (docs/lcm.md §10).
  sequencer_.set_max_busy_timeouts(pipeline::RefitWaitTimeouts(
      options_.refit_wait_s, !bus_.options().key_path.empty(), options_.timeout_ms));
  if (options_.hold_at >= 0) {
    if (!options_.lockstep) throw std::invalid_argument("--hold-at needs lockstep mode");
    sequencer_.HoldAt(options_.hold_at);
    release_.add(SIGUSR1);
    WaitForRelease();
  }
  const auto& ch = bus_.channels();
  bus_.Subscribe<odonata::plant_state_t>(ch.state, [this](const auto& m) { OnState(m); });
  bus_.Subscribe<odonata::control_t>(ch.control, [this](const auto& m) { OnControl(m); });
  if (options_.lockstep) {
    // A consumer whose messages this signed generator refuses (no key, another key) cannot be
    // waited for: the lossless promise does not hold for it. Said at once, naming it, and the
    // run's exit code says so (kExitConsumerRefused). It is not a reason to stop: a forger's
    // heartbeat looks the same, and the authentic consumers lose nothing.
    bus_.OnRefused([this](const std::string& channel, const uint8_t* data, std::size_t size,
                          bus::MessageSigner::Verdict verdict) {
      // Stale and replayed messages carry the system's key: captured traffic sent again (a
      // consumer's own earlier heartbeats among it), not a consumer without the key.
      using Verdict = bus::MessageSigner::Verdict;
      if (verdict != Verdict::kUnsigned && verdict != Verdict::kBadTag) return;
      if (finished_ || channel != bus_.channels().heartbeat) return;
      odonata::heartbeat_t h;
      if (!bus::SafeDecode(&h, data, static_cast<int64_t>(size))) return;
      if (h.service != "odonata-identifier" && h.service != "odonata-logger") return;
      if (refused_consumers_.size() >= 16 || !refused_consumers_.insert(h.instance).second) return;
      if (options_.refused_consumers_fail) {
        // A lossless run that cannot hear one of its consumers stops now, naming it, rather
        // than run on for minutes and say so at the end (a forger's heartbeat looks the same:
        // --keep-going-without-refused for a bus where forgers may speak).
        Finish(kExitConsumerRefused,
               "'" + h.instance + "' (" + h.service +
                   ") is heard but its messages are refused as " +
                   bus::MessageSigner::Describe(verdict) +
                   ": its receipts cannot count, so the run cannot be lossless for it; start it "
                   "with the system's --key");
        return;
      }
      std::fprintf(stderr,
                   "[%s] WARNING: '%s' (%s) is heard but its messages are refused as %s: its "
                   "receipts cannot count, so this run does not wait for it and it may miss "
                   "samples; start it with the system's --key\n",
                   bus_.options().instance.c_str(), h.instance.c_str(), h.service.c_str(),
                   bus::MessageSigner::Describe(verdict));
    });
    bus_.Subscribe<odonata::ack_t>(ch.ack, [this](const auto& m) { OnAck(m); });
    for (const std::string& name : options_.wait_for) sequencer_.AddConsumer(name);
    if (options_.discover_s > 0) {
      bus_.Subscribe<odonata::heartbeat_t>(ch.heartbeat, [this](const auto& m) { OnHeartbeat(m); });
      sequencer_.HoldStart();
      bus_.After(std::chrono::microseconds(static_cast<int64_t>(options_.discover_s * 1e6)),
                 [this] {
                   if (finished_) return;
                   std::string names;
                   for (const auto& [name, acked] : sequencer_.consumers()) names += " " + name;
                   std::fprintf(stderr, "[%s] lockstep waits for receipts from:%s\n",
                                bus_.options().instance.c_str(),
                                names.empty() ? " nobody" : names.c_str());
                   Apply(sequencer_.ReleaseStart());
                 });
    }
  }
  bus_.OnShutdown([this] {
    if (options_.progress && !finished_) std::fputc('\n', stderr);  // end the progress line
    if (!finished_ && bus_.stopped_by_signal()) {
      std::fprintf(stderr,
                   "odonata-signal: stopped by a signal after %lld of %zu commands: the run is "
                   "not complete\n",
                   static_cast<long long>(commands_sent_), schedule_.size());
      if (plant_restarts_ > 0) {
        std::fprintf(stderr,
                     "odonata-signal: %s restarted %lld time(s) during it (first at command "
                     "%lld)\n",
                     options_.plant.c_str(), static_cast<long long>(plant_restarts_),
                     static_cast<long long>(first_restart_command_));
      }
      bus_.SetExitCode(kExitInterrupted);
    }
    finished_ = true;
    timer_.cancel();
    boost::system::error_code ignored;
    release_.cancel(ignored);
  });
  if (!options_.lockstep && !options_.reset_plant) {
    StartRealtime();  // real time without a reset does not wait for the plant at all
    return;
  }
  bus_.SetState("waiting");
  const pipeline::SequencerAction first = sequencer_.Start();
  Apply(first);
  if (first.kind == pipeline::SequencerAction::Kind::kNone) ArmTimeout();
}

void SignalNode::OnState(const odonata::plant_state_t& msg) {
  if (finished_) return;
  if (realtime_started_) {
    WatchRealtimeState(msg);
    return;
  }
  ++states_received_;
  Apply(sequencer_.OnState(msg.seq, msg.command_seq,
                           msg.status == odonata::plant_state_t::STATUS_DIVERGED));
}

void SignalNode::WatchRealtimeState(const odonata::plant_state_t& msg) {
  // A real-time plant that was killed and started again numbers its states from 0 and flies on
  // with the commands: the run goes on, but the log (and the identifier) hold it in two parts,
  // which a script must not take for one whole run.
  const bool start = msg.seq == 0 && msg.command_seq < 0;
  if (plant_run_.Next(msg.seq, start).kind != pipeline::RunVerdict::Kind::kRestart) return;
  if (plant_restarts_++ == 0) first_restart_command_ = next_realtime_;
  std::fprintf(stderr,
               "[%s] WARNING: %s restarted at command %lld (its states began again at 0): the log "
               "holds this run in %lld parts\n",
               bus_.options().instance.c_str(), options_.plant.c_str(),
               static_cast<long long>(next_realtime_), static_cast<long long>(plant_restarts_ + 1));
}

void SignalNode::OnAck(const odonata::ack_t& msg) {
  if (finished_) return;
  if (sequencer_.consumers().count(msg.instance) > 0) ++receipts_received_;
  Apply(sequencer_.OnAck(msg.instance, msg.state_seq));
}

void SignalNode::OnHeartbeat(const odonata::heartbeat_t& msg) {
  if (finished_) return;
  if (msg.service != "odonata-identifier" && msg.service != "odonata-logger") return;
  const bool known = sequencer_.consumers().count(msg.instance) > 0;
  // An identifier landing a scheduled refit acknowledges nothing until it has: patience, not
  // resends (docs/lcm.md §10).
  const bool refitting = msg.state == "refitting";
  // An identifier landing a refit (after a freeze, its closing one) reads again once it has:
  // it is a consumer like a running one, and one this run must wait for.
  if (!known && (msg.state == "running" || msg.state == "frozen" || refitting)) {
    sequencer_.AddConsumer(msg.instance);
    if (sequencer_.phase() != pipeline::LockstepSequencer::Phase::kAwaitingInitial) {
      std::fprintf(stderr, "[%s] %s joined mid-run: waiting for its receipts too\n",
                   bus_.options().instance.c_str(), msg.instance.c_str());
    }
  }
  // Ignored for an instance that is not a consumer, so one call serves a known consumer and one
  // just added.
  sequencer_.SetBusy(msg.instance, refitting);
  if (known && (msg.state == "stopping" || msg.state == "error")) {
    // It leaves with what it has; the rest of the run goes on for the others, but the run failed
    // it, and says so at the end.
    consumer_left_ = msg.instance + " (" + msg.state + " at command " +
                     std::to_string(sequencer_.current()) + ")";
    std::fprintf(stderr, "[%s] WARNING: consumer %s left mid-run; it misses the rest\n",
                 bus_.options().instance.c_str(), consumer_left_.c_str());
    Apply(sequencer_.RemoveConsumer(msg.instance));
  }
}

void SignalNode::OnControl(const odonata::control_t& msg) {
  // Its own RESET of the plant comes back on the bus: not a command to the generator.
  if (msg.sender == bus_.options().instance || !bus_.AcceptControl(msg)) return;
  const auto params = [&] {
    return std::vector<std::pair<std::string, double>>{
        {"commands_sent", static_cast<double>(commands_sent_)}};
  };
  if (msg.command == odonata::control_t::SHUTDOWN) {
    bus_.ReplyControl(msg, true, "stopping", params());
    bus_.Stop(0);
  } else if (msg.command == odonata::control_t::GET) {
    bus_.ReplyControl(msg, true, "parameters in force", params());
  } else {
    bus_.RejectUnsupported(msg);
  }
}

void SignalNode::Apply(const pipeline::SequencerAction& action) {
  using Kind = pipeline::SequencerAction::Kind;
  switch (action.kind) {
    case Kind::kNone:
      // The window slid without anything left to send: the timeout counts from here.
      if (action.progressed && options_.lockstep) ArmTimeout();
      if (sequencer_.holding()) AnnounceHold();
      return;
    case Kind::kSendReset:
      SendReset();
      ArmTimeout();
      return;
    case Kind::kSendCommand:
      if (!options_.lockstep) {
        StartRealtime();  // the plant is fresh: from here on the clock paces the run
        return;
      }
      bus_.SetState("running");
      if (!first_command_) first_command_ = std::chrono::steady_clock::now();
      for (int64_t k = action.seq; k < action.seq + action.count; ++k) SendCommand(k);
      ArmTimeout();
      ShowProgress(sequencer_.current(), false);
      return;
    case Kind::kFinished:
      ShowProgress(sequencer_.command_count(), true);
      if (!consumer_left_.empty()) {
        Finish(kExitConsumerLost, "every command was answered, but consumer " + consumer_left_ +
                                      " left before the end: it misses samples");
        return;
      }
      Finish(0, "");
      return;
    case Kind::kFailed: {
      const bool diverged = action.failure == pipeline::SequencerAction::Failure::kDiverged;
      std::string message =
          action.message + " (plant '" + options_.plant + "' on " + bus_.channels().state + ")";
      if (action.failure == pipeline::SequencerAction::Failure::kNoAnswer) {
        message += " after " + std::to_string(options_.max_resends) + " resend(s) " +
                   std::to_string(options_.timeout_ms) + " ms apart: is " + options_.plant +
                   " running, on the same --lcm-url and --channel-suffix?";
        // The answers may have come and been refused: then that is the cause to name.
        if (bus_.unauthenticated() > 0)
          message += " " + std::to_string(bus_.unauthenticated()) +
                     " messages were refused here, the last " + bus_.last_refusal();
      }
      const bool consumer = action.failure == pipeline::SequencerAction::Failure::kConsumerLost;
      if (consumer) message = action.message;
      Finish(diverged ? kExitDiverged : consumer ? kExitConsumerLost : kExitNoPlant, message);
      return;
    }
  }
}

void SignalNode::AnnounceHold() {
  if (hold_announced_) return;
  hold_announced_ = true;
  std::fprintf(stderr,
               "[%s] holding before command %lld: every state up to %lld is confirmed; SIGUSR1 "
               "resumes\n",
               bus_.options().instance.c_str(), static_cast<long long>(options_.hold_at),
               static_cast<long long>(options_.hold_at));
  std::fflush(stderr);
}

void SignalNode::WaitForRelease() {
  release_.async_wait([this](const boost::system::error_code& ec, int) {
    if (ec || finished_) return;
    if (!sequencer_.holding()) {  // too early: the hold stands, and so does the wait
      std::fprintf(stderr, "[%s] SIGUSR1 before the hold was reached: ignored\n",
                   bus_.options().instance.c_str());
      WaitForRelease();
      return;
    }
    std::fprintf(stderr, "[%s] released at command %lld\n", bus_.options().instance.c_str(),
                 static_cast<long long>(options_.hold_at));
    Apply(sequencer_.ReleaseHold());
  });
}

void SignalNode::ArmTimeout() {
  // Only the deadline moves per command: re-arming the timer each time would cancel its wait,
  // and the cancelled handler costs the loop an extra wake-up per sample. The wait, when it
  // fires early, sleeps on to the deadline.
  timeout_deadline_ =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(options_.timeout_ms);
  if (!timeout_armed_) WaitForTimeout();
}

void SignalNode::WaitForTimeout() {
  timeout_armed_ = true;
  const uint64_t generation = timer_generation_;
  timer_.expires_at(timeout_deadline_);
  timer_.async_wait([this, generation](const boost::system::error_code& ec) {
    timeout_armed_ = false;
    if (ec || finished_ || generation != timer_generation_) return;
    if (std::chrono::steady_clock::now() < timeout_deadline_) {
      WaitForTimeout();
      return;
    }
    const pipeline::SequencerAction action = sequencer_.OnTimeout();
    const std::string notice = sequencer_.patience().Notice(
        options_.timeout_ms, sequencer_.Waited(), !bus_.options().key_path.empty());
    if (!notice.empty())
      std::fprintf(stderr, "[%s] %s\n", bus_.options().instance.c_str(), notice.c_str());
    Apply(action);
    // Waiting again for a plant that was not reset: nothing was sent, but the clock restarts.
    if (action.kind == pipeline::SequencerAction::Kind::kNone && !finished_) ArmTimeout();
  });
}

void SignalNode::StartRealtime() {
  realtime_started_ = true;
  // After a reset the plant's state 0 has been seen; without one its numbering is unknown.
  // The run rule with confirmation, and far below: a real-time plant resends nothing, so two
  // consecutive low seqs are its restart even when its state 0 was lost.
  plant_run_ = pipeline::RunStart(pipeline::kRealtimeStates, options_.reset_plant ? 0 : -1);
  bus_.SetState("running");
  ++timer_generation_;
  pacer_ = pipeline::RealtimePacer(std::chrono::steady_clock::now());
  timer_.expires_at(pacer_.start());
  RealtimeTick();
}

void SignalNode::RealtimeTick() {
  if (finished_) return;
  SendCommand(next_realtime_);
  ShowProgress(next_realtime_, false);
  if (++next_realtime_ == static_cast<int64_t>(schedule_.size())) {
    ShowProgress(next_realtime_, true);
    if (plant_restarts_ > 0) {
      Finish(kExitPlantRestarted,
             "every command was sent, but " + options_.plant + " restarted " +
                 std::to_string(plant_restarts_) + " time(s) mid-run (first at command " +
                 std::to_string(first_restart_command_) + "): the log holds the run in " +
                 std::to_string(plant_restarts_ + 1) +
                 " parts (odonata-logger export --run picks one)");
      return;
    }
    Finish(0, "");
    return;
  }
  // Each command at its own time from the start: the rate does not drift with latency.
  timer_.expires_at(pacer_.DueAtSample(next_realtime_, options_.rate_hz));
  const uint64_t generation = timer_generation_;
  timer_.async_wait([this, generation](const boost::system::error_code& ec) {
    if (!ec && generation == timer_generation_) RealtimeTick();
  });
}

void SignalNode::SendCommand(int64_t k) {
  bus_.Publish(bus_.channels().command,
               messages::ToCommandMessage(schedule_, static_cast<std::size_t>(k), bus::NowUtime()));
  ++commands_sent_;
}

void SignalNode::SendReset() {
  odonata::control_t c{};
  c.utime = bus::NowUtime();
  c.seq = control_seq_++;
  c.sender = "odonata-signal";
  c.target = options_.plant;
  c.command = odonata::control_t::RESET;
  c.path = schedule_.setup_name;  // the preset's initial condition ("" = the plant's own)
  bus_.Publish(bus_.channels().control, c);
}

void SignalNode::ShowProgress(int64_t k, bool last) {
  if (!options_.progress) return;
  const auto now = std::chrono::steady_clock::now();
  if (!last && now - last_progress_ < kProgressPeriodMs) return;
  last_progress_ = now;
  std::fprintf(stderr, "\rsample %lld of %zu", static_cast<long long>(k), schedule_.size());
  if (last) std::fputc('\n', stderr);
  std::fflush(stderr);
}

void SignalNode::Finish(int exit_code, const std::string& message) {
  if (finished_) return;
  finished_ = true;
  ++timer_generation_;
  timer_.cancel();
  if (exit_code == 0) {
    bus_.SetState("finished");
    std::string rate;
    if (first_command_) {  // lockstep: how fast the whole loop ran, discovery excluded
      const double s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - *first_command_).count();
      char text[96];
      std::snprintf(text, sizeof text, " in %.3f s (%.0f samples/s)", s,
                    s > 0 ? static_cast<double>(schedule_.size()) / s : 0.0);
      rate = text;
    }
    std::fprintf(stderr,
                 "[%s] sent %zu commands (%s)%s, %lld resend(s), %lld for missing receipts\n",
                 bus_.options().instance.c_str(), schedule_.size(), schedule_.source.c_str(),
                 rate.c_str(), static_cast<long long>(sequencer_.total_resends()),
                 static_cast<long long>(sequencer_.ack_resends()));
    if (sequencer_.busy_timeouts() > 0) {
      std::fprintf(stderr,
                   "[%s] waited %lld timeout(s) for consumers landing a scheduled refit (nothing "
                   "resent meanwhile)\n",
                   bus_.options().instance.c_str(),
                   static_cast<long long>(sequencer_.busy_timeouts()));
    }
    if (sequencer_.impossible_acks() > 0) {
      std::fprintf(stderr,
                   "[%s] %lld receipt(s) for states beyond the newest command were ignored (a "
                   "consumer's previous run, or forged)\n",
                   bus_.options().instance.c_str(),
                   static_cast<long long>(sequencer_.impossible_acks()));
    }
    if (!refused_consumers_.empty()) {
      std::string names;
      for (const auto& n : refused_consumers_) names += (names.empty() ? "" : ", ") + n;
      std::fprintf(stderr,
                   "odonata-signal: error: every command sent, but without receipts from %s, "
                   "whose messages were refused (no or another key): the run was not lossless "
                   "for them\n",
                   names.c_str());
      exit_code = kExitConsumerRefused;
      bus_.SetState("error: consumers refused: " + names);
    }
    if (first_command_) {
      // The messages each sample cost the protocol: its hops, and what loss or a slow
      // consumer added (docs/lcm.md §10).
      const double n = static_cast<double>(schedule_.size());
      std::fprintf(stderr,
                   "[%s] lockstep window %d: per sample %.2f commands sent, %.2f states and "
                   "%.2f receipts (from %zu consumers) received\n",
                   bus_.options().instance.c_str(), sequencer_.window(),
                   static_cast<double>(commands_sent_) / n,
                   static_cast<double>(states_received_) / n,
                   static_cast<double>(receipts_received_) / n, sequencer_.consumers().size());
    }
  } else {
    bus_.SetState("error");
    bus_.stats().last_error = message;
    std::fprintf(stderr, "odonata-signal: error: %s\n", message.c_str());
  }
  bus_.Stop(exit_code);
}

}  // namespace odonata::signal_service
