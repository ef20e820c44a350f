#include "logger_node.hpp"

#include "odonata/beat_state_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/wing_command_t.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

namespace odonata::logger {

LoggerNode::LoggerNode(bus::BusNode& bus, const RecordOptions& options)
    : bus_(bus),
      options_(options),
      writer_(options.prefix, options.split_bytes),
      acks_(bus, bus.channels().ack) {
  bus_.SubscribeRaw(
      options_.channels_regex, [this](const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
        // LCM 1.3.1 hands on a datagram whose channel name has no terminating NUL with
        // data_size -1 (4294967295 unsigned); written, it would make the rest of the log
        // unreadable.
        if (rbuf.data_size > INT32_MAX || (rbuf.data == nullptr && rbuf.data_size > 0)) {
          ++bus_.stats().decode_errors;
          bus_.Report("malformed datagram", "on '" + channel + "' with data size " +
                                                std::to_string(rbuf.data_size) + ": not logged");
          return;
        }
        writer_.Write(rbuf.recv_utime, channel, rbuf.data, static_cast<int32_t>(rbuf.data_size));
        Track(channel, rbuf);
      });
  // SHUTDOWN reaches the logger too: it closes its files (OnShutdown below) like on SIGTERM.
  bus_.Subscribe<odonata::control_t>(bus_.channels().control, [this](const odonata::control_t& m) {
    if (!bus_.AcceptControl(m)) return;
    const std::vector<std::pair<std::string, double>> params{
        {"events", static_cast<double>(writer_.events())},
        {"bytes", static_cast<double>(writer_.bytes())},
        {"files", static_cast<double>(writer_.files().size())}};
    if (m.command == odonata::control_t::SHUTDOWN) {
      bus_.ReplyControl(m, true, "stopping: the log is flushed and closed on the way out", params);
      bus_.Stop(0);
    } else if (m.command == odonata::control_t::GET) {
      bus_.ReplyControl(m, true, "recording", params);
    } else {
      bus_.RejectUnsupported(m);
    }
  });
  bus_.Every(std::chrono::microseconds(static_cast<int64_t>(options_.flush_period_s * 1e6)),
             [this] { writer_.Flush(); });
  bus_.OnShutdown([this] {
    writer_.Close();
    std::fprintf(stderr, "[%s] %lld events, %.1f kB in", bus_.options().instance.c_str(),
                 static_cast<long long>(writer_.events()), writer_.bytes() / 1e3);
    for (const auto& f : writer_.files()) std::fprintf(stderr, " %s", f.c_str());
    std::fprintf(stderr, "\n");
  });
  bus_.SetState("running");
}

void LoggerNode::Track(const std::string& channel, const lcm::ReceiveBuffer& rbuf) {
  const auto& ch = bus_.channels();
  int64_t state_seq = -1;
  // Written already whatever it holds; only genuine-looking seqs move the receipt.
  // A fresh state 0 is a new run (a plant reset): states and commands start their marks afresh,
  // as a fresh beat state 0 does for the beat states. Nothing else moves a mark back, so a stale
  // or forged seq can never stall the receipts.
  if (channel == ch.state) {
    odonata::plant_state_t m;
    if (!bus::SafeDecode(&m, rbuf.data, rbuf.data_size) || m.seq < 0) return;
    const bool fresh = m.seq == 0 && m.command_seq < 0;
    if (fresh) commands_ = ContiguousMark{};
    states_.Add(m.seq, fresh);
    state_seq = m.seq;
  } else if (channel == ch.command) {
    odonata::wing_command_t m;
    if (!bus::SafeDecode(&m, rbuf.data, rbuf.data_size) || m.seq < 0) return;
    commands_.Add(m.seq);
  } else if (channel == ch.beat_state) {
    odonata::beat_state_t m;
    if (!bus::SafeDecode(&m, rbuf.data, rbuf.data_size) || m.seq < 0) return;
    beats_.Add(m.seq, m.seq == 0 && m.command_seq < 0);
    beats_seen_ = true;
  } else {
    return;
  }
  // State s is held with all it needs once command s - 1 (which it answers) and beat state s
  // (published right after it) are written too.
  int64_t held = std::min(states_.mark(), commands_.mark() + 1);
  if (beats_seen_) held = std::min(held, beats_.mark());
  acks_.Publish(held, state_seq);
}

}  // namespace odonata::logger
