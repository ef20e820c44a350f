#include "mavlink_node.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include <boost/asio/buffer.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/write.hpp>

#include "bus/socket_buffer.hpp"
#include "mavlink/tlog_file.hpp"
#include "odonata/control_t.hpp"
#include "odonata/signals_t.hpp"

namespace odonata::mavlink_service {
namespace {

using Clock = std::chrono::steady_clock;
namespace asio = boost::asio;

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

MavlinkNode::MavlinkNode(bus::BusNode& bus, mavlink::BridgeOptions bridge,
                         MavlinkNodeOptions options)
    : bus_(bus),
      options_(std::move(options)),
      core_([&] {
        // The requester sees every frame first: it learns there that the vehicle is heard.
        bridge.on_frame = [this](const mavlink::Frame& f) { requester_.Observe(f); };
        return std::move(bridge);
      }()),
      requester_(options_.requests, options_.target_system, options_.target_component),
      start_(Clock::now()) {
  if (options_.link.kind == LinkKind::kUdp) {
    boost::system::error_code ec;
    const auto address = asio::ip::make_address(options_.link.udp_address, ec);
    if (ec) throw std::runtime_error("--udp: '" + options_.link.udp_address + "' is no IP address");
    udp_.emplace(bus_.io());
    const asio::ip::udp::endpoint at(address, static_cast<unsigned short>(options_.link.udp_port));
    udp_->open(at.protocol(), ec);
    if (!ec) udp_->bind(at, ec);
    if (ec)
      throw std::runtime_error("cannot listen on UDP " + options_.link.udp_address + ":" +
                               std::to_string(options_.link.udp_port) + ": " + ec.message() +
                               " (is a ground station listening there already? give --udp "
                               "another port and forward to it)");
    udp_port_ = udp_->local_endpoint().port();
    // A flood, or the vehicle's burst while this process is off the CPU, waits in the kernel.
    bus::SetReceiveBuffer(udp_->native_handle(), bus::kDefaultReceiveBuffer);
    std::fprintf(stderr, "odonata-mavlink: listening on UDP %s:%u\n",
                 options_.link.udp_address.c_str(), udp_port());
    ReceiveDatagram();
  } else {
    boost::system::error_code ec;
    serial_.emplace(bus_.io());
    serial_->open(options_.link.serial_device, ec);
    if (!ec) serial_->set_option(asio::serial_port_base::baud_rate(options_.link.baud), ec);
    if (!ec) serial_->set_option(asio::serial_port_base::character_size(8), ec);
    if (!ec)
      serial_->set_option(asio::serial_port_base::parity(asio::serial_port_base::parity::none), ec);
    if (!ec)
      serial_->set_option(asio::serial_port_base::stop_bits(asio::serial_port_base::stop_bits::one),
                          ec);
    if (!ec)
      serial_->set_option(
          asio::serial_port_base::flow_control(asio::serial_port_base::flow_control::none), ec);
    if (ec)
      throw std::runtime_error("cannot open the serial port " + options_.link.serial_device +
                               " at " + std::to_string(options_.link.baud) +
                               " baud: " + ec.message());
    std::fprintf(stderr, "odonata-mavlink: reading %s at %u baud\n",
                 options_.link.serial_device.c_str(), options_.link.baud);
    ReadSerial();
  }
  bus_.SetState("waiting");
  bus_.Every(std::chrono::seconds(1), [this] { Tick(); });
  // GET answers with the counts, SHUTDOWN stops it as SIGTERM does (its summary still printed).
  bus_.Subscribe<odonata::control_t>(bus_.channels().control, [this](const odonata::control_t& m) {
    if (!bus_.AcceptControl(m)) return;
    const mavlink::DecoderCounters& c = core_.counters();
    const std::vector<std::pair<std::string, double>> params{
        {"frames", static_cast<double>(c.frames_ok)},
        {"frames_dropped", static_cast<double>(c.dropped() + core_.bridge_dropped())},
        {"frames_lost", static_cast<double>(core_.sequences().lost())},
        {"published", static_cast<double>(published_)},
        {"gap_samples", static_cast<double>(core_.gap_samples())},
        {"rate_hz", core_.rate_hz()}};
    if (m.command == odonata::control_t::SHUTDOWN) {
      bus_.ReplyControl(m, true, "stopping", params);
      bus_.Stop(0);
    } else if (m.command == odonata::control_t::GET) {
      bus_.ReplyControl(m, true, core_.rate_note(), params);
    } else {
      bus_.RejectUnsupported(m);
    }
  });
  bus_.OnShutdown([this] {
    if (udp_) udp_->close();
    if (serial_) serial_->close();
  });
}

double MavlinkNode::Now() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

void MavlinkNode::ReceiveDatagram() {
  udp_->async_receive_from(asio::buffer(buffer_), sender_,
                           [this](const boost::system::error_code& ec, std::size_t n) {
                             if (ec == asio::error::operation_aborted) return;
                             if (!ec) {
                               ++datagrams_;
                               if (options_.link.datagrams == DatagramFormat::kTlogRecord)
                                 OnStampedDatagram(n);
                               else
                                 OnBytes(buffer_.data(), n, BytesEnd::kDatagramEnds, Now());
                             }
                             ReceiveDatagram();
                           });
}

void MavlinkNode::ReadSerial() {
  serial_->async_read_some(
      asio::buffer(buffer_), [this](const boost::system::error_code& ec, std::size_t n) {
        if (ec == asio::error::operation_aborted) return;
        if (ec) {
          // A radio unplugged: said once, the service stops with an error (nothing more comes).
          bus_.Report("serial", options_.link.serial_device + ": " + ec.message());
          bus_.Stop(1);
          return;
        }
        OnBytes(buffer_.data(), n, BytesEnd::kStreamGoesOn, Now());
        ReadSerial();
      });
}

void MavlinkNode::OnStampedDatagram(std::size_t size) {
  constexpr std::size_t kStampBytes = mavlink::kTlogTimestampSize;
  if (size < kStampBytes) {
    ++short_datagrams_;
    bus_.Report("datagram", "a datagram of " + std::to_string(size) +
                                " bytes holds no .tlog record stamp: dropped");
    return;
  }
  const std::uint64_t stamp_us = mavlink::TlogStampAt(buffer_.data());
  if (!first_stamp_us_) first_stamp_us_ = stamp_us;
  const double t_s = mavlink::TlogSeconds(stamp_us, *first_stamp_us_);
  OnBytes(buffer_.data() + kStampBytes, size - kStampBytes, BytesEnd::kDatagramEnds, t_s);
}

void MavlinkNode::OnBytes(const char* data, std::size_t size, BytesEnd end, double now) {
  bytes_ += static_cast<std::int64_t>(size);
  const bool heard_before = requester_.target_heard();
  core_.Feed(std::string_view(data, size), now);
  if (end == BytesEnd::kDatagramEnds) core_.EndOfDatagram(now);
  // Over UDP the vehicle is where its datagrams come from: answers go there.
  if (udp_ && requester_.target_heard() && !heard_before) vehicle_ = sender_;
  PublishReady();
  if (!heard_before && requester_.target_heard()) SendRequests(Now());
}

void MavlinkNode::PublishReady() {
  for (const mavlink::GridSample& s : core_.TakeSamples()) {
    if (s.gap()) continue;  // counted in the core; its seq is missing downstream
    odonata::signals_t m;
    m.utime = bus::NowUtime();
    m.seq = s.k;
    m.source = options_.source;
    m.num_signals = static_cast<int32_t>(s.values.size());
    m.names = core_.field_names();
    m.values = s.values;
    bus_.Publish(bus_.channels().signals, m);
    ++published_;
  }
  if (!rate_said_ && core_.rate_hz() > 0.0) {
    rate_said_ = true;
    std::fprintf(stderr, "odonata-mavlink: %s\n", core_.rate_note().c_str());
    bus_.SetState("running");
  }
}

void MavlinkNode::Tick() {
  const double now = Now();
  const mavlink::DecoderCounters& c = core_.counters();
  bus::ServiceStats& st = bus_.stats();
  st.messages_in = static_cast<int64_t>(c.frames_ok);
  st.decode_errors = static_cast<int64_t>(c.dropped());
  st.dropped = static_cast<int64_t>(core_.bridge_dropped());
  st.gaps = static_cast<int64_t>(core_.sequences().lost());
  st.skipped = static_cast<int64_t>(core_.gap_samples());
  std::vector<std::string> silent = core_.Silent(now);
  if (!silent.empty() && silent != silent_) {
    const std::string text = "no " + Join(silent) + " for " +
                             std::to_string(static_cast<int>(core_.silence_s())) +
                             " s: is the vehicle sending it (--request-rate asks for it)?";
    std::fprintf(stderr, "odonata-mavlink: warning: %s\n", text.c_str());
    st.last_error = text;
  }
  silent_ = std::move(silent);
  for (const auto& [message, senders] : core_.other_senders()) {
    for (const std::string& sender : senders) {
      if (!warned_senders_.insert(message + "@" + sender).second) continue;
      const std::string text = message + " also comes from " + sender +
                               ", which no field takes (a plain name follows the first sender "
                               "heard); name " +
                               message + "@" + sender + ".FIELD to take that one";
      std::fprintf(stderr, "odonata-mavlink: warning: %s\n", text.c_str());
      st.last_error = text;
    }
  }
  SendRequests(now);
}

void MavlinkNode::SendRequests(double now_s) {
  for (const std::string& frame : requester_.Due(now_s)) {
    if (!options_.signing_key) {
      SendToVehicle(frame);
      continue;
    }
    last_signing_timestamp_ = std::max(mavlink::SigningTimestampNow(), last_signing_timestamp_ + 1);
    SendToVehicle(mavlink::SignFrameV2(frame, *options_.signing_key, 0, last_signing_timestamp_));
  }
}

void MavlinkNode::SendToVehicle(const std::string& frame) {
  boost::system::error_code ec;
  if (udp_ && vehicle_)
    udp_->send_to(asio::buffer(frame), *vehicle_, 0, ec);
  else if (serial_)
    asio::write(*serial_, asio::buffer(frame), ec);
  if (ec) bus_.Report("request", "could not send a rate request: " + ec.message());
}

nlohmann::json MavlinkNode::Summary() const {
  nlohmann::json j = core_.Summary();
  j["link"] =
      udp_ ? nlohmann::json{{"udp", options_.link.udp_address + ":" + std::to_string(udp_port())}}
           : nlohmann::json{{"serial", options_.link.serial_device}, {"baud", options_.link.baud}};
  j["datagrams"] = datagrams_;
  j["bytes"] = bytes_;
  j["short_datagrams"] = short_datagrams_;
  j["published"] = published_;
  j["requests"] = requester_.Summary();
  return j;
}

std::string MavlinkNode::SummaryLine() const {
  const mavlink::DecoderCounters& c = core_.counters();
  std::string line = std::to_string(published_) + " samples published (" +
                     std::to_string(core_.gap_samples()) + " with a gap, not sent) from " +
                     std::to_string(c.frames_ok) +
                     " frames; dropped: " + std::to_string(c.bad_crc) + " bad checksum, " +
                     std::to_string(c.unknown_message) + " unknown message, " +
                     std::to_string(c.bad_signature + core_.unsigned_refused()) + " signature, " +
                     std::to_string(core_.bridge_dropped()) + " other sender or out of order; " +
                     std::to_string(core_.sequences().lost()) + " frames lost on the link";
  for (const std::string& s : requester_.Status()) line += "\n  request " + s;
  return line;
}

}  // namespace odonata::mavlink_service
