#pragma once
// odonata-mavlink's process shell: a vehicle's MAVLink link — the UDP port a ground station
// listens on, or a telemetry radio's serial port — onto the bus as VEHICLE_SIGNALS, the fields a
// user names on one grid (mavlink/bridge_core.hpp does all of that; this file only moves bytes).
//
// Inputs:  MAVLink 1 and 2 frames (UDP datagrams, or a serial byte stream); ODONATA_CONTROL (GET
//          answers with the counts, SHUTDOWN stops it)
// Outputs: VEHICLE_SIGNALS (signals_t: seq = the grid index k, so a grid sample with a gap is not
//          sent and its consumers count it missing); with --request-rate, COMMAND_LONG frames to
//          the vehicle (rate_request.hpp); nothing else is ever sent to it.
// Heartbeat: messages_in = frames decoded, decode_errors = frames the decoder dropped (bad
//          checksum, unknown message, bad signature, incompatible, cut), dropped = frames the
//          bridge dropped (another sender, unsigned with a key, out of order), gaps = MAVLink
//          sequence numbers skipped (frames lost on the link), skipped = grid samples not sent
//          (a gap), last_error = a named field silent for --silence seconds.

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <boost/asio/ip/udp.hpp>
#include <boost/asio/serial_port.hpp>
#include <nlohmann/json.hpp>

#include "bus/bus_node.hpp"
#include "mavlink/bridge_core.hpp"
#include "mavlink/link_signature.hpp"
#include "mavlink/rate_request.hpp"

namespace odonata::mavlink_service {

/// Where the link is heard.
enum class LinkKind : std::uint8_t { kUdp, kSerial };

/// What one UDP datagram holds.
enum class DatagramFormat : std::uint8_t {
  kFrames,      ///< MAVLink frames, as a vehicle sends them: each timed by its arrival
  kTlogRecord,  ///< one .tlog record (8-byte big-endian µs stamp, then the frame): timed by its
                ///< stamp, from the first one heard, as odonata-fit reads the .tlog (a recording
                ///< replayed with its own times: equal to the offline reading)
};

struct LinkOptions {
  LinkKind kind = LinkKind::kUdp;
  DatagramFormat datagrams = DatagramFormat::kFrames;
  std::string udp_address = "0.0.0.0";  ///< where a ground station listens
  unsigned udp_port = 14550;            ///< MAVLink's ground-station port
  std::string serial_device;            ///< a telemetry radio: /dev/ttyUSB0
  unsigned baud = 57600;                ///< SiK radios' default
};

struct MavlinkNodeOptions {
  LinkOptions link;
  std::string source = "mavlink";  ///< signals_t.source
  std::vector<mavlink::RateRequest> requests;
  std::uint8_t target_system = 1, target_component = 1;  ///< whom --request-rate asks
  /// The link's key (--signing-key): what is sent to the vehicle is signed with it, as a vehicle
  /// that enforces signing requires.
  std::optional<mavlink::LinkKey> signing_key;
};

class MavlinkNode {
 public:
  /// Opens the link (throws std::runtime_error naming it when it cannot: a port in use, a device
  /// missing) and starts listening.
  MavlinkNode(bus::BusNode& bus, mavlink::BridgeOptions bridge, MavlinkNodeOptions options);
  /// Counts, grid and fields (BridgeCore::Summary) with what was published and requested.
  nlohmann::json Summary() const;
  std::string SummaryLine() const;
  /// The UDP port listened on (the one given, or the kernel's choice for port 0).
  unsigned udp_port() const { return udp_port_; }

 private:
  void ReceiveDatagram();
  void ReadSerial();
  void OnStampedDatagram(std::size_t size);
  /// Whether the bytes end a datagram (UDP carries whole frames) or a stream goes on (serial).
  enum class BytesEnd : std::uint8_t { kStreamGoesOn, kDatagramEnds };
  // `now`: the time base of the bytes (their arrival, or a stamp).
  void OnBytes(const char* data, std::size_t size, BytesEnd end, double now);
  void PublishReady();
  void Tick();  // once a second: counts into the heartbeat, silent fields, rate requests
  void SendRequests(double now_s);
  void SendToVehicle(const std::string& frame);
  double Now() const;

  bus::BusNode& bus_;
  MavlinkNodeOptions options_;
  mavlink::BridgeCore core_;
  mavlink::RateRequester requester_;
  std::chrono::steady_clock::time_point start_;
  std::optional<boost::asio::ip::udp::socket> udp_;
  boost::asio::ip::udp::endpoint sender_;                  // of the datagram being received
  std::optional<boost::asio::ip::udp::endpoint> vehicle_;  // the target's address, once heard
  std::optional<boost::asio::serial_port> serial_;
  unsigned udp_port_ = 0;  // bound
  std::array<char, 65536> buffer_{};
  std::int64_t published_ = 0;
  std::int64_t datagrams_ = 0;
  std::int64_t bytes_ = 0;
  std::int64_t short_datagrams_ = 0;             // kTlogRecord: shorter than a stamp, dropped
  std::optional<std::uint64_t> first_stamp_us_;  // kTlogRecord: the time base
  std::vector<std::string> silent_;              // the last Silent() reported
  bool rate_said_ = false;
  std::uint64_t last_signing_timestamp_ = 0;  // each signed frame's newer than the last
  std::set<std::string> warned_senders_;      // "ATTITUDE@2:1" said once
};

}  // namespace odonata::mavlink_service
