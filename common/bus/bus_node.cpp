#include "bus/bus_node.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <boost/asio/post.hpp>

#include "bus/udpm_channel_filter.hpp"
#include "odonata/heartbeat_t.hpp"

namespace odonata::bus {

int64_t NowUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

namespace {

// SIGINT/SIGTERM seen, even while a handler blocks the loop (a landing waiting for its refit):
// asio's own handler only queues the signal for the loop, so ours runs first and chains to it.
volatile std::sig_atomic_t g_stop_signal = 0;
struct sigaction g_asio_handlers[2];

extern "C" void NoteStopSignal(int sig) {
  g_stop_signal = 1;
  const struct sigaction& next = g_asio_handlers[sig == SIGINT ? 0 : 1];
  if (next.sa_handler != SIG_DFL && next.sa_handler != SIG_IGN) next.sa_handler(sig);
}

void ChainStopSignals() {
  for (const int sig : {SIGINT, SIGTERM}) {
    struct sigaction current {};
    if (sigaction(sig, nullptr, &current) != 0 || current.sa_handler == NoteStopSignal) continue;
    g_asio_handlers[sig == SIGINT ? 0 : 1] = current;
    struct sigaction ours = current;
    ours.sa_handler = NoteStopSignal;
    sigaction(sig, &ours, nullptr);
  }
}

}  // namespace

bool BusNode::stop_requested() const { return g_stop_signal != 0 || stop_begun_; }

BusNode::BusNode(const BusOptions& options)
    : options_(options),
      lcm_(std::make_unique<lcm::LCM>(options.lcm_url)),
      lcm_fd_(io_),
      signals_(io_, SIGINT, SIGTERM) {
  if (options_.instance.empty()) options_.instance = options_.service;
  if (!options_.key_path.empty()) {
    signer_ = std::make_unique<MessageSigner>(
        LoadBusKey(options_.key_path),
        options_.sender_id != 0 ? options_.sender_id : RandomSenderId(), started_utime_);
  }
  if (!lcm_->good()) {
    throw std::runtime_error(
        "cannot open LCM at '" +
        (options.lcm_url.empty() ? std::string("the default URL") : options.lcm_url) +
        "' (is there a multicast route? see docs/guide/live-system.md, 'Networking')");
  }
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  host_ = host;
  const char* receive = std::getenv("ODONATA_LCM_RECEIVE");
  const auto endpoint = ParseUdpmEndpoint(EffectiveLcmUrl(options.lcm_url));
  if (endpoint && !(receive != nullptr && std::string(receive) == "lcm")) {
    // getFileno() is never called and LCM never subscribes, so LCM starts no receive thread.
    receiver_ = std::make_unique<UdpmReceiver>(
        io_, *endpoint,
        [this](const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
          if (!stopping_) Dispatch(rbuf, channel);
        },
        [this](bool malformed, const std::string& message) {
          ++(malformed ? stats_.decode_errors : stats_.dropped);
          Report(malformed ? "malformed datagram" : "incomplete message", message);
        },
        [this](int64_t n) {
          stats_.dropped += n;
          Report("receive buffer full",
                 std::to_string(receiver_->kernel_dropped()) +
                     " datagrams dropped by the kernel so far before this process read them (it "
                     "was off the CPU, or the bus was flooded); raise recv_buf_size in the URL");
        });
    sender_ = std::make_unique<UdpmSender>(*endpoint);
  } else {
    lcm_fd_.assign(lcm_->getFileno());
    // Non-blocking, so a wake-up that finds no message makes handle() return an error instead
    // of blocking the whole service (it cannot happen while the pipe holds a byte per waiting
    // queue, but a hang would stop every timer and the heartbeat with it).
    const int flags = fcntl(lcm_->getFileno(), F_GETFL);
    if (flags < 0 || fcntl(lcm_->getFileno(), F_SETFL, flags | O_NONBLOCK) < 0)
      throw std::runtime_error("cannot make LCM's notify descriptor non-blocking");
    WaitForLcm();
  }
  ChainStopSignals();
  signals_.async_wait([this](const boost::system::error_code& ec, int) {
    if (ec) return;
    stopped_by_signal_ = true;
    Stop(0);
  });
  if (options_.heartbeat_period_s > 0) {
    Every(std::chrono::microseconds(static_cast<int64_t>(options_.heartbeat_period_s * 1e6)),
          [this] { PublishHeartbeat(); });
  }
}

BusNode::~BusNode() {
  // LCM owns the descriptor: Asio must not close it.
  if (lcm_fd_.is_open()) lcm_fd_.release();
}

void BusNode::Trampoline(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         RawHandler* h) {
  if (h->active) h->fn(rbuf, channel);
}

bool BusNode::SendBytes(const std::string& channel, const std::vector<uint8_t>& bytes) {
  if (sender_ && UdpmSender::Fits(channel, bytes.size()))
    return sender_->Send({{&channel, bytes.data(), bytes.size()}});
  return lcm_->publish(channel, bytes.data(), static_cast<unsigned int>(bytes.size())) == 0;
}

const lcm::ReceiveBuffer* BusNode::Authenticate(const lcm::ReceiveBuffer* rbuf,
                                                const std::string& channel) {
  if (!signer_) {
    // A process without the key on a signed bus: it cannot tell the system's messages from
    // forgeries, and the system refuses every one it sends. Said at once, not found out later.
    if (!heard_signed_ && LooksSigned(static_cast<const uint8_t*>(rbuf->data), rbuf->data_size)) {
      heard_signed_ = true;
      Report("no key on a signed bus",
             "messages on " + channel +
                 " are signed, but this process has no --key: the signed services refuse "
                 "everything it sends, and it cannot tell their messages from forged ones; start "
                 "it with the system's key");
    }
    return rbuf;
  }
  if (rbuf != &stripped_) {
    const auto* bytes = static_cast<const uint8_t*>(rbuf->data);
    std::array<uint8_t, kSignatureBytes> trailer{};
    if (rbuf->data_size >= kSignatureBytes)
      std::memcpy(trailer.data(), bytes + rbuf->data_size - kSignatureBytes, kSignatureBytes);
    const bool same = checked_.data == rbuf->data && checked_.recv_utime == rbuf->recv_utime &&
                      checked_.size == rbuf->data_size && checked_.trailer == trailer;
    if (!same) {
      std::size_t payload = 0;
      const auto verdict = signer_->Verify(channel, bytes, rbuf->data_size, NowUtime(), &payload);
      checked_ = {rbuf->data, rbuf->recv_utime, rbuf->data_size, trailer,
                  verdict == MessageSigner::Verdict::kAuthentic};
      if (!checked_.authentic) {
        ++unauthenticated_;
        ++stats_.dropped;
        last_refusal_ = "on " + channel + ": " + MessageSigner::Describe(verdict);
        Report("refused message on " + channel, MessageSigner::Describe(verdict));
        if (on_refused_) on_refused_(channel, bytes, rbuf->data_size, verdict);
      } else {
        stripped_ = *rbuf;
        stripped_.data_size = static_cast<uint32_t>(payload);
      }
    }
    if (!checked_.authentic) return nullptr;
  }
  return &stripped_;
}

void BusNode::SubscribeRaw(
    const std::string& regex,
    std::function<void(const lcm::ReceiveBuffer&, const std::string&)> handler) {
  handlers_.push_back(RawHandler{this, regex, nullptr, {}});
  RawHandler& h = handlers_.back();
  h.fn = [this, handler = std::move(handler)](const lcm::ReceiveBuffer* rbuf,
                                              const std::string& channel) {
    rbuf = Authenticate(rbuf, channel);  // refused: counted as dropped, not as a message in
    if (rbuf == nullptr) return;
    ++stats_.messages_in;
    try {
      handler(*rbuf, channel);
    } catch (const std::exception& e) {
      ++stats_.dropped;
      Report("failed to handle a message on " + channel, e.what());
    }
  };
  Register(h);
}

void BusNode::Register(RawHandler& h) {
  if (receiver_) {
    try {
      h.pattern = std::regex(h.channel, std::regex::ECMAScript | std::regex::optimize);
    } catch (const std::regex_error& e) {
      throw std::runtime_error("invalid channel name or regex '" + h.channel + "': " + e.what());
    }
    routes_stale_ = true;
    UpdateFilter();
    return;
  }
  // LCM 1.3.1 keeps only 30 undelivered messages per subscription and drops the rest without
  // telling anyone; a lockstep burst while this process is off the CPU can exceed that.
  lcm_->subscribeFunction(h.channel, &BusNode::Trampoline, &h)->setQueueCapacity(kQueueCapacity);
}

void BusNode::UpdateFilter() {
  if (!receiver_) return;
  // The kernel drops what no subscription wants, while every subscription is a plain name, and
  // every fragment when no subscription can take a fragmented message.
  std::vector<std::string> names;
  bool fragments = false;
  for (const auto& h : handlers_) {
    if (!h.active) continue;
    if (!IsLiteralChannel(h.channel)) {
      receiver_->Filter(std::nullopt, true);
      return;
    }
    names.push_back(h.channel);
    fragments = fragments || h.fragments;
  }
  receiver_->Filter(names, fragments);
}

void BusNode::Unsubscribe(const void* subscription) {
  for (auto& h : handlers_)
    if (&h == subscription) h.active = false;
  routes_stale_ = true;
  UpdateFilter();
}

void BusNode::Dispatch(const lcm::ReceiveBuffer& rbuf, const std::string& channel) {
  // Cleared here, never while a handler runs: a handler may subscribe, and the loop below walks
  // the cached list by reference.
  if (routes_stale_ || routes_.size() >= kMaxRoutes) {
    routes_.clear();
    routes_stale_ = false;
  }
  auto it = routes_.find(channel);
  if (it == routes_.end()) {
    std::vector<RawHandler*> matching;
    // LCM anchors every subscription: the whole name must match.
    for (auto& h : handlers_)
      if (h.active && std::regex_match(channel, h.pattern)) matching.push_back(&h);
    it = routes_.emplace(channel, std::move(matching)).first;
  }
  if (it->second.empty()) return;
  const lcm::ReceiveBuffer* message = Authenticate(&rbuf, channel);
  if (message == nullptr) return;
  for (RawHandler* h : it->second) {
    if (stopping_) return;
    if (h->active) h->fn(message, channel);
  }
}

void BusNode::WaitForLcm() {
  lcm_fd_.async_wait(boost::asio::posix::stream_descriptor::wait_read,
                     [this](const boost::system::error_code& ec) {
                       if (ec || stopping_) return;
                       // One message per wake-up, through handle() rather than handleTimeout(0):
                       // the wake-up already says a message is queued, and handleTimeout's
                       // select() cost two system calls per message (one finding it, one
                       // finding the queue empty). LCM keeps its notify pipe readable while
                       // messages remain, so the next wait fires at once, and timers get their
                       // turn between messages. Both receive paths: docs/lcm.md §9.
                       lcm_->handle();
                       WaitForLcm();
                     });
}

void BusNode::ArmTimer(std::shared_ptr<boost::asio::steady_timer> timer,
                       std::chrono::microseconds period, std::function<void()> fn) {
  timer->expires_at(timer->expiry() + period);
  timer->async_wait([this, timer, period, fn](const boost::system::error_code& ec) {
    if (ec || stopping_) return;
    fn();
    ArmTimer(timer, period, fn);
  });
}

void BusNode::Every(std::chrono::microseconds period, std::function<void()> fn) {
  auto timer = std::make_shared<boost::asio::steady_timer>(io_);
  timer->expires_at(std::chrono::steady_clock::now());
  timers_.push_back(timer);
  ArmTimer(timer, period, std::move(fn));
}

void BusNode::After(std::chrono::microseconds delay, std::function<void()> fn) {
  auto timer = std::make_shared<boost::asio::steady_timer>(io_, delay);
  timers_.push_back(timer);
  const auto it = std::prev(timers_.end());
  timer->async_wait([this, it, fn = std::move(fn)](const boost::system::error_code& ec) {
    if (ec || stopping_) return;  // Stop() cancels and keeps the list intact
    timers_.erase(it);            // one-shot: forget it, or a timer per call would pile up
    fn();
  });
}

int BusNode::Run() {
  PublishHeartbeat();
  io_.run();
  return exit_code_;
}

void BusNode::Stop(int exit_code) {
  // The worst thing the service saw stands: a SIGTERM or SHUTDOWN (code 0) after a divergence
  // (SetExitCode(3)) must not turn the run's exit into a success.
  if (exit_code_ == 0) exit_code_ = exit_code;
  if (stopping_ || stop_begun_) return;  // a handler of the messages drained below stops too
  stop_begun_ = true;
  // What reached this process before the stop is handled, not closed on with the socket: a
  // sample queued at SIGTERM is learned or counted, a message queued for the logger recorded.
  if (receiver_) receiver_->DrainQueued(kMostDrainedAtStop);
  SetState("stopping");
  if (on_shutdown_) {
    try {
      on_shutdown_();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "[%s] shutdown: %s\n", options_.service.c_str(), e.what());
      if (exit_code_ == 0) exit_code_ = 1;
    }
  }
  stopping_ = true;
  boost::system::error_code ignored;
  signals_.cancel(ignored);
  if (lcm_fd_.is_open()) lcm_fd_.cancel(ignored);
  if (receiver_) receiver_->Close();
  for (auto& t : timers_) t->cancel();
  io_.stop();
}

void BusNode::SetState(const std::string& state) {
  if (state == state_) return;
  state_ = state;
  PublishHeartbeat();
}

void BusNode::PublishHeartbeat() {
  // A one-shot tool (odonata-control) sends none: a monitor would list it, then warn that it
  // went silent once it had done its job and exited.
  if (options_.one_shot) return;
  odonata::heartbeat_t hb;
  hb.utime = NowUtime();
  hb.seq = heartbeat_seq_++;
  hb.service = options_.service;
  hb.instance = options_.instance;
  hb.host = host_;
  hb.pid = static_cast<int32_t>(getpid());
  hb.state = state_;
  hb.messages_in = stats_.messages_in;
  hb.messages_out = stats_.messages_out;
  hb.decode_errors = stats_.decode_errors;
  hb.dropped = stats_.dropped;
  hb.gaps = stats_.gaps;
  hb.skipped = stats_.skipped;
  hb.repeated = stats_.repeated;
  hb.last_error = stats_.last_error;
  hb.detail = stats_.detail;
  Publish(options_.channels.heartbeat, hb);
}

bool BusNode::AcceptControl(const odonata::control_t& msg) {
  if (!AddressedTo(msg, options_.instance, options_.service)) return false;
  // A message without a publish time cannot be told from another one: it is obeyed every time.
  for (const auto& a : answered_) {
    if (msg.utime != 0 && a.seq == msg.seq && a.utime == msg.utime && a.sender == msg.sender) {
      Publish(options_.channels.control_reply, a.reply);  // the first answer was lost: again
      return false;
    }
  }
  if (msg.utime != 0 && msg.utime < started_utime_ - kStaleControl) {
    ++stats_.dropped;
    // In unsigned arithmetic: a forged utime near INT64_MIN must not overflow the difference.
    const uint64_t age_us =
        static_cast<uint64_t>(started_utime_) - static_cast<uint64_t>(msg.utime);
    stats_.last_error = "ignored " + ControlCommandName(msg.command) + " from '" + msg.sender +
                        "' published " + std::to_string(age_us / 1'000'000) +
                        " s before this service started (a replayed log?)";
    std::fprintf(stderr, "[%s] %s\n", options_.instance.c_str(), stats_.last_error.c_str());
    return false;
  }
  const std::string refusal = ControlRefusal(msg, options_.control_senders);
  if (refusal.empty()) return true;
  ++stats_.dropped;
  stats_.last_error = "refused " + refusal;
  std::fprintf(stderr, "[%s] refused %s\n", options_.instance.c_str(), refusal.c_str());
  ReplyControl(msg, false, refusal);
  return false;
}

void BusNode::RejectUnsupported(const odonata::control_t& msg) {
  if (!AddressedByName(msg, options_.instance, options_.service)) return;
  ReplyControl(msg, false, options_.service + " has no '" + ControlCommandName(msg.command) + "'");
}

void BusNode::ReplyControl(const odonata::control_t& request, bool accepted,
                           const std::string& reason,
                           const std::vector<std::pair<std::string, double>>& params) {
  odonata::control_reply_t r{};
  r.utime = NowUtime();
  r.seq = reply_seq_++;
  r.request_sender = request.sender;
  r.request_seq = request.seq;
  r.command = request.command;
  r.service = options_.service;
  r.instance = options_.instance;
  r.accepted = accepted;
  r.reason = reason;
  r.num_params = static_cast<int32_t>(params.size());
  for (const auto& [name, value] : params) {
    r.names.push_back(name);
    r.values.push_back(value);
  }
  Publish(options_.channels.control_reply, r);
  answered_.push_front({request.sender, request.seq, request.utime, r});
  if (answered_.size() > kMaxAnswered) answered_.pop_back();
}

void BusNode::Report(const std::string& kind, const std::string& message) {
  stats_.Report(options_.instance, kind, message);
}

}  // namespace odonata::bus
