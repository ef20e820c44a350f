#pragma once
// One process's LCM endpoint inside one Boost.Asio event loop: its receive path, timers,
// SIGINT/SIGTERM, typed subscriptions that count undecodable messages, and the heartbeat.
// Over udpm the node reads the multicast socket itself (UdpmReceiver); other providers
// (memq:// in tests), or ODONATA_LCM_RECEIVE=lcm, keep LCM's own receive thread. Both paths are
// in docs/lcm.md §9.

#include <array>
#include <chrono>
#include <functional>
#include <list>
#include <memory>
#include <regex>
#include <string>
#include <unordered_map>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <lcm/lcm-cpp.hpp>

#include "bus/channel_config.hpp"
#include "bus/control_gate.hpp"
#include "bus/message_signer.hpp"
#include "bus/safe_decode.hpp"
#include "bus/service_stats.hpp"
#include "bus/udpm_receiver.hpp"
#include "bus/udpm_sender.hpp"
#include "odonata/control_reply_t.hpp"
#include "odonata/model_snapshot_t.hpp"
#include "odonata/signals_t.hpp"

namespace odonata::bus {

/// Whether a message of this type can outgrow one udpm datagram, so that LCM sends it in LC03
/// fragments: a model snapshot (it grows with the rules), a vehicle's signals (as many as it
/// names). A node none of whose subscriptions can take one has the kernel drop every fragment
/// on the group (udpm_channel_filter): a flood of large messages, unsigned or not, then costs it
/// no reassembly and no room in its receive buffer (docs/lcm.md §9).
template <class Msg>
inline constexpr bool kMayBeFragmented = false;
template <>
inline constexpr bool kMayBeFragmented<odonata::model_snapshot_t> = true;
template <>
inline constexpr bool kMayBeFragmented<odonata::signals_t> = true;

/// Microseconds since the UNIX epoch, LCM's utime.
int64_t NowUtime();

struct BusOptions {
  std::string lcm_url;   ///< empty ⇒ LCM_DEFAULT_URL or udpm ttl=0
  std::string service;   ///< e.g. odonata-identifier
  std::string instance;  ///< unique name of this copy (defaults to service)
  ChannelConfig channels;
  double heartbeat_period_s = 1.0;  ///< 0: only on a change of state
  /// A one-shot tool (odonata-control, a tool that only asks): no heartbeat at all, so
  /// a monitor neither lists it nor warns that it went silent once it has done its job.
  bool one_shot = false;
  /// Senders whose RESET and SHUTDOWN this process obeys (control_gate.hpp).
  std::vector<std::string> control_senders = DefaultControlSenders();
  /// The shared key's file (message_signer.hpp; empty: no key). With a key every message this
  /// node publishes is signed, and every message it receives must be signed with the same key
  /// and new: the rest is counted as dropped, reported, and never reaches a handler.
  std::string key_path;
  /// The sender id its signatures carry (0: a random one, as a service wants).
  uint64_t sender_id = 0;
};

class BusNode {
 public:
  /// Messages LCM may hold per subscription before it drops (its default is 30).
  static constexpr int kQueueCapacity = 100000;

  /// @throws std::runtime_error when LCM cannot be opened (bad URL, no multicast route).
  explicit BusNode(const BusOptions& options);
  ~BusNode();
  BusNode(const BusNode&) = delete;
  BusNode& operator=(const BusNode&) = delete;

  /// Subscribes to `channel` (exact name). The handler receives only messages that decode;
  /// the rest are counted as decode errors and reported once per channel. Exceptions thrown
  /// by the handler are caught, counted as dropped and reported, so bad input never kills the
  /// process.
  /// Returns the subscription, for Unsubscribe.
  template <class Msg>
  const void* Subscribe(const std::string& channel, std::function<void(const Msg&)> handler);

  /// Stops delivering messages to `subscription` (Subscribe's result: a service that needs a
  /// channel only while it starts, as the identifier needs snapshots to resume), and narrows the
  /// kernel's filter to what is left. Safe inside a handler.
  void Unsubscribe(const void* subscription);

  /// Subscribes to every channel matching `regex` without decoding (recorders): the handler
  /// gets the raw buffer and the channel name. Counts messages_in.
  void SubscribeRaw(const std::string& regex,
                    std::function<void(const lcm::ReceiveBuffer&, const std::string&)> handler);

  /// Encodes and publishes; counts messages_out. Returns false (and reports) on failure.
  template <class Msg>
  bool Publish(const std::string& channel, const Msg& msg);
  /// Publishes two messages in one system call over udpm, so no receiver woken by the first
  /// preempts this process before the second leaves (the plant's state and beat state).
  template <class A, class B>
  bool PublishTogether(const std::string& channel_a, const A& a, const std::string& channel_b,
                       const B& b);

  /// Calls fn every `period` until the loop stops (first call after one period).
  void Every(std::chrono::microseconds period, std::function<void()> fn);
  /// Calls fn once after `delay`.
  void After(std::chrono::microseconds delay, std::function<void()> fn);
  /// Called on SIGINT/SIGTERM (and Stop()) before the loop ends: flush files here.
  void OnShutdown(std::function<void()> fn) { on_shutdown_ = std::move(fn); }
  /// True once SIGINT or SIGTERM stopped the loop (not the service's own Stop()).
  bool stopped_by_signal() const { return stopped_by_signal_; }
  /// True once SIGINT or SIGTERM arrived or Stop() began, even while a handler blocks the loop
  /// (so that a long wait inside one can give up and let the stop happen).
  bool stop_requested() const;
  /// The code Run() returns, for a shutdown hook that learns the run did not finish.
  void SetExitCode(int code) { exit_code_ = code; }
  int exit_code() const { return exit_code_; }

  /// Runs the loop until Stop() or a signal. Returns the process exit code.
  int Run();
  /// Stops the loop; `exit_code` becomes Run()'s unless a non-zero code was set before (the
  /// worst thing the service saw is what it exits with). Over udpm, the messages already queued
  /// on the socket (at most kMostDrainedAtStop) reach their handlers first.
  void Stop(int exit_code = 0);
  /// Datagrams a stop reads off the socket at most before it closes it.
  static constexpr std::size_t kMostDrainedAtStop = 100000;

  /// Sets the heartbeat state, publishing a heartbeat at once when it changes.
  void SetState(const std::string& state);
  const std::string& state() const { return state_; }
  void PublishHeartbeat();
  /// True when this process should act on `msg`: addressed to it and, for RESET and SHUTDOWN,
  /// from an allowed sender. A refusal is counted as dropped and logged, every time, and
  /// answered (ReplyControl, rejected, with the reason). A command this process has already
  /// answered, resent because the answer was lost (same sender, seq and non-zero utime), is not
  /// obeyed again: its answer is published again instead. A command published well before this
  /// process started (utime more than kStaleControl earlier) is a replayed log's — lcm-logplayer
  /// keeps the recorded utime —, not an operator's: it is counted as dropped, logged, and not
  /// answered (a replay must not steer a live system by surprise; docs/lcm.md §13).
  bool AcceptControl(const odonata::control_t& msg);
  /// Clocks of two boards may disagree by a few seconds; a replayed log is older than this.
  static constexpr int64_t kStaleControl = 30'000'000;  // µs
  /// Answers `request` on the control_reply channel: accepted or rejected with `reason`, and the
  /// parameters in force afterwards. Every service answers each command addressed to it by name,
  /// and each it acts on when addressed to all (docs/lcm.md §13).
  void ReplyControl(const odonata::control_t& request, bool accepted, const std::string& reason,
                    const std::vector<std::pair<std::string, double>>& params = {});
  /// Answers a command this service has no use for: rejected when it was named as the target,
  /// nothing when the command went to every service (it is for the others).
  void RejectUnsupported(const odonata::control_t& msg);
  /// Records a problem (counts nothing by itself; callers bump the right counter).
  void Report(const std::string& kind, const std::string& message);

  ServiceStats& stats() { return stats_; }
  const BusOptions& options() const { return options_; }
  const ChannelConfig& channels() const { return options_.channels; }
  boost::asio::io_context& io() { return io_; }
  lcm::LCM& lcm() { return *lcm_; }
  /// True when this node reads udpm itself rather than through LCM's receive thread.
  bool own_receiver() const { return receiver_ != nullptr; }
  /// True when it signs what it publishes and takes only what is signed (BusOptions::key_path).
  bool signing() const { return signer_ != nullptr; }
  /// Datagrams the kernel dropped before this process read them (its receive buffer was full;
  /// counted in stats().dropped as well). 0 on other providers than udpm.
  int64_t kernel_dropped() const { return receiver_ ? receiver_->kernel_dropped() : 0; }
  /// Messages refused for their signature (counted in stats().dropped as well).
  int64_t unauthenticated() const { return unauthenticated_; }
  /// The last message refused by the signature check, and why ("on DIMAV_STATE: stale …"):
  /// what a "no answer" should name, since the answer may have come and been refused.
  const std::string& last_refusal() const { return last_refusal_; }
  /// Called with each message the signature check refuses, undecoded (channel, bytes, why): a
  /// lockstep sender learns that a consumer it must wait for cannot be heard (a keyless service
  /// on a signed bus) instead of quietly not waiting for it.
  using RefusalHandler = std::function<void(const std::string& channel, const uint8_t* data,
                                            std::size_t size, MessageSigner::Verdict verdict)>;
  void OnRefused(RefusalHandler handler) { on_refused_ = std::move(handler); }
  /// Without a key: signed messages were heard (a misconfigured board on a signed system).
  bool heard_signed() const { return heard_signed_; }

 private:
  struct RawHandler {
    BusNode* node;
    std::string channel;  ///< a regex, as LCM reads every subscription
    std::function<void(const lcm::ReceiveBuffer*, const std::string&)> fn;
    std::regex pattern;     ///< for the own receiver
    bool fragments = true;  ///< its messages may come in fragments (kMayBeFragmented)
    bool active = true;     ///< false once unsubscribed
  };
  static void Trampoline(const lcm::ReceiveBuffer* rbuf, const std::string& channel, RawHandler* h);
  void Register(RawHandler& h);
  /// The kernel's filter for the subscriptions in force (udpm_channel_filter).
  void UpdateFilter();
  /// The message's bytes in `buffer`, signed when the node has a key; empty when it cannot be
  /// encoded.
  template <class Msg>
  std::vector<uint8_t>& Encode(const std::string& channel, const Msg& msg,
                               std::vector<uint8_t>& buffer);
  /// Sends encoded bytes: over the own sender when they fit one datagram, else through LCM
  /// (which fragments, and serves other providers).
  bool SendBytes(const std::string& channel, const std::vector<uint8_t>& bytes);
  /// With a key: the received message without its signature when it is authentic and new, else
  /// nullptr (counted and reported). Without a key: `rbuf` itself. LCM's receive thread hands
  /// one message to each matching subscription in turn: the verdict on it is kept for the others.
  const lcm::ReceiveBuffer* Authenticate(const lcm::ReceiveBuffer* rbuf,
                                         const std::string& channel);
  void Dispatch(const lcm::ReceiveBuffer& rbuf, const std::string& channel);
  void WaitForLcm();
  void ArmTimer(std::shared_ptr<boost::asio::steady_timer> timer, std::chrono::microseconds period,
                std::function<void()> fn);

  BusOptions options_;
  boost::asio::io_context io_;
  std::unique_ptr<lcm::LCM> lcm_;
  boost::asio::posix::stream_descriptor lcm_fd_;
  boost::asio::signal_set signals_;
  std::list<RawHandler> handlers_;  // stable addresses: LCM keeps raw pointers to them
  std::unique_ptr<UdpmReceiver> receiver_;
  std::unique_ptr<UdpmSender> sender_;
  std::unique_ptr<MessageSigner> signer_;
  int64_t unauthenticated_ = 0;
  std::string last_refusal_;
  RefusalHandler on_refused_;
  bool heard_signed_ = false;
  struct Checked {  // Authenticate()'s last verdict, for the next subscription's turn
    const void* data = nullptr;
    int64_t recv_utime = 0;
    uint32_t size = 0;
    std::array<uint8_t, kSignatureBytes> trailer{};  // the signature bytes it carried
    bool authentic = false;
  } checked_;
  lcm::ReceiveBuffer stripped_{};
  std::vector<uint8_t> encoded_[2];
  // Channel name -> its handlers, so each name is matched against the regexes once; bounded, as
  // forged traffic may bring any number of names.
  std::unordered_map<std::string, std::vector<RawHandler*>> routes_;
  static constexpr std::size_t kMaxRoutes = 1024;
  bool routes_stale_ = false;  // a subscription was added: rebuild at the next message
  std::list<std::shared_ptr<boost::asio::steady_timer>> timers_;
  std::function<void()> on_shutdown_;
  ServiceStats stats_;
  std::string state_ = "starting";
  bool stopped_by_signal_ = false;
  std::string host_;
  int64_t heartbeat_seq_ = 0;
  int64_t started_utime_ = NowUtime();
  int64_t reply_seq_ = 0;
  // The newest answers, by their request's sender, seq and utime, to answer a resend again.
  struct AnsweredControl {
    std::string sender;
    int64_t seq, utime;
    odonata::control_reply_t reply;
  };
  std::list<AnsweredControl> answered_;
  static constexpr std::size_t kMaxAnswered = 32;
  int exit_code_ = 0;
  bool stopping_ = false;
  bool stop_begun_ = false;  ///< Stop() has begun: it drains the socket before it stops
};

template <class Msg>
const void* BusNode::Subscribe(const std::string& channel,
                               std::function<void(const Msg&)> handler) {
  handlers_.push_back(RawHandler{this, channel, nullptr, {}, kMayBeFragmented<Msg>});
  RawHandler& h = handlers_.back();
  h.fn = [this, channel, handler = std::move(handler)](const lcm::ReceiveBuffer* rbuf,
                                                       const std::string&) {
    rbuf = Authenticate(rbuf, channel);  // refused: counted as dropped, not as a message in
    if (rbuf == nullptr) return;
    ++stats_.messages_in;
    Msg msg;
    if (!SafeDecode(&msg, rbuf->data, rbuf->data_size)) {
      ++stats_.decode_errors;
      Report("undecodable message on " + channel,
             std::to_string(rbuf->data_size) + " bytes that are not a valid " + Msg::getTypeName() +
                 " (wrong type, truncated or corrupt)");
      return;
    }
    try {
      handler(msg);
    } catch (const std::exception& e) {
      ++stats_.dropped;
      Report("rejected message on " + channel, e.what());
    }
  };
  Register(h);
  return &h;
}

template <class Msg>
std::vector<uint8_t>& BusNode::Encode(const std::string& channel, const Msg& msg,
                                      std::vector<uint8_t>& buffer) {
  const int size = msg.getEncodedSize();
  buffer.resize(static_cast<std::size_t>(size));
  if (msg.encode(buffer.data(), 0, size) != size)
    buffer.clear();
  else if (signer_)
    signer_->Sign(channel, &buffer, NowUtime());
  return buffer;
}

template <class Msg>
bool BusNode::Publish(const std::string& channel, const Msg& msg) {
  bool ok = false;
  if (signer_ ||
      (sender_ && UdpmSender::Fits(channel, static_cast<std::size_t>(msg.getEncodedSize())))) {
    const auto& bytes = Encode(channel, msg, encoded_[0]);
    ok = !bytes.empty() && SendBytes(channel, bytes);
  } else {
    ok = lcm_->publish(channel, &msg) == 0;  // other providers, and messages LCM fragments
  }
  if (!ok) {
    Report("publish failed on " + channel, "the message could not be sent");
    return false;
  }
  ++stats_.messages_out;
  return true;
}

template <class A, class B>
bool BusNode::PublishTogether(const std::string& channel_a, const A& a,
                              const std::string& channel_b, const B& b) {
  const std::size_t extra = signer_ ? kSignatureBytes : 0;
  if (!sender_ ||
      !UdpmSender::Fits(channel_a, static_cast<std::size_t>(a.getEncodedSize()) + extra) ||
      !UdpmSender::Fits(channel_b, static_cast<std::size_t>(b.getEncodedSize()) + extra)) {
    const bool first = Publish(channel_a, a);
    return Publish(channel_b, b) && first;
  }
  const auto& bytes_a = Encode(channel_a, a, encoded_[0]);
  const auto& bytes_b = Encode(channel_b, b, encoded_[1]);
  if (bytes_a.empty() || bytes_b.empty() ||
      !sender_->Send({{&channel_a, bytes_a.data(), bytes_a.size()},
                      {&channel_b, bytes_b.data(), bytes_b.size()}})) {
    Report("publish failed on " + channel_a + " and " + channel_b,
           "the messages could not be sent");
    return false;
  }
  stats_.messages_out += 2;
  return true;
}

}  // namespace odonata::bus
