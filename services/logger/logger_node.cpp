#include "logger_node.hpp"

#include "bus/event_log_format.hpp"
#include "odonata/beat_state_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/signals_t.hpp"
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
      acks_(bus, bus.channels().ack),
      signal_acks_(bus, bus.channels().signals_ack) {
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
        const auto size = static_cast<int64_t>(rbuf.data_size);
        if (options_.max_event_bytes > 0 && size > options_.max_event_bytes) {
          ++bus_.stats().dropped;
          bus_.Report("oversize message", std::to_string(size) + " bytes on '" + channel +
                                              "', over --max-event-kb: not logged");
          return;
        }
        if (options_.max_bytes > 0 &&
            writer_.bytes() + bus::LogEventBytes(channel.size(), size) > options_.max_bytes) {
          ++bus_.stats().dropped;
          if (!over_budget_) {
            over_budget_ = true;
            bus_.SetState("disk budget spent: not recording");
            bus_.Report("disk budget", "the recording reached --max-mb (" +
                                           std::to_string(writer_.bytes()) +
                                           " bytes): nothing more is written");
          }
          return;
        }
        writer_.Write(rbuf.recv_utime, channel, rbuf.data, static_cast<int32_t>(size));
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
    // Its own loss: datagrams the kernel dropped before it read them are not in the log.
    if (bus_.kernel_dropped() > 0)
      std::fprintf(stderr,
                   "[%s] WARNING: %lld datagrams were dropped by the kernel before the logger read "
                   "them (receive buffer full): the log misses them\n",
                   bus_.options().instance.c_str(), static_cast<long long>(bus_.kernel_dropped()));
  });
  bus_.SetState("running");
}

void LoggerNode::Track(const std::string& channel, const lcm::ReceiveBuffer& rbuf) {
  const auto& ch = bus_.channels();
  int64_t state_seq = -1;
  // Written already whatever it holds; only genuine-looking seqs move the receipt.
  if (channel == ch.state) {
    odonata::plant_state_t m;
    if (!bus::SafeDecode(&m, rbuf.data, rbuf.data_size) || m.seq < 0) return;
    marks_.OnState(m.seq, m.command_seq < 0);
    state_seq = m.seq;
  } else if (channel == ch.command) {
    odonata::wing_command_t m;
    if (!bus::SafeDecode(&m, rbuf.data, rbuf.data_size) || m.seq < 0) return;
    marks_.OnCommand(m.seq);
  } else if (channel == ch.beat_state) {
    odonata::beat_state_t m;
    if (!bus::SafeDecode(&m, rbuf.data, rbuf.data_size) || m.seq < 0) return;
    marks_.OnBeat(m.seq);
  } else if (channel == ch.signals) {
    odonata::signals_t m;
    if (!bus::SafeDecode(&m, rbuf.data, rbuf.data_size) || m.seq < 0) return;
    // A resend of the newest (its receipt was lost) is answered again; an accepted sample
    // moves the receipt. Flushed first, as for states: a receipt says the sample is safe.
    const bool resend = m.seq == signals_sequence_.newest();
    if (!resend &&
        signals_sequence_.Next(m.seq).kind == pipeline::SampleSequence::Verdict::Kind::kDrop)
      return;
    writer_.Flush();
    signal_acks_.Publish(signals_sequence_.newest(), m.seq);
    return;
  } else {
    return;
  }
  const int64_t held = marks_.held();
  // A receipt says the events are safe: they must have left this process's buffer first, or a
  // kill -9 loses what the generator will never resend (the page cache survives the process).
  if (held >= 0 && held != flushed_held_) {  // != : a new run starts its marks again
    writer_.Flush();
    flushed_held_ = held;
  }
  acks_.Publish(held, state_seq);
}

}  // namespace odonata::logger
