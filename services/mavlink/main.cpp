// odonata-mavlink: a vehicle's MAVLink link (PX4, ArduPilot: the UDP port a ground station
// listens on, or a telemetry radio's serial port) onto the bus as VEHICLE_SIGNALS, the fields a
// user names on one grid, so the live identifier, monitor and logger run next to the vehicle.

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus_cli/bus_options.hpp"
#include "cli/parse_command_line.hpp"
#include "io/atomic_file.hpp"
#include "mavlink/link_signature.hpp"
#include "mavlink_node.hpp"

namespace {

// "[ADDRESS:]PORT" → the link's address and port.
void ParseUdp(const std::string& text, odonata::mavlink_service::LinkOptions& link) {
  const auto colon = text.rfind(':');
  const std::string port = colon == std::string::npos ? text : text.substr(colon + 1);
  if (colon != std::string::npos) link.udp_address = text.substr(0, colon);
  std::size_t used = 0;
  unsigned long n = 0;
  try {
    n = std::stoul(port, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (port.empty() || used != port.size() || n > 65535)
    throw std::runtime_error("--udp takes [ADDRESS:]PORT (e.g. 14550 or 0.0.0.0:14550), not '" +
                             text + "'");
  link.udp_port = static_cast<unsigned>(n);
}

// "SYSID:COMPID" → the two numbers.
void ParseTarget(const std::string& text, odonata::mavlink_service::MavlinkNodeOptions& o) {
  unsigned a = 0, b = 0;
  char end = 0;
  if (std::sscanf(text.c_str(), "%u:%u%c", &a, &b, &end) != 2 || a > 255 || b > 255)
    throw std::runtime_error("--target takes SYSID:COMPID, two numbers 0..255 (e.g. 1:1), not '" +
                             text + "'");
  o.target_system = static_cast<std::uint8_t>(a);
  o.target_component = static_cast<std::uint8_t>(b);
}

}  // namespace

int main(int argc, char** argv) {
  odonata::cli::BusCliOptions bus_options;
  bus_options.instance = "mavlink";
  odonata::mavlink::BridgeOptions bridge;
  odonata::mavlink_service::MavlinkNodeOptions o;
  std::string udp = "14550", target = "1:1", key_path, summary_json;
  std::vector<std::string> requests;
  CLI::App app{
      "Listens to a vehicle's MAVLink link (PX4, ArduPilot) where a ground station would — a UDP "
      "port, or a telemetry radio's serial port — and publishes the fields you name as "
      "VEHICLE_SIGNALS (signals_t) on one grid, for the identifier, monitor and logger. Counts "
      "every frame it drops (bad checksum, unknown message, another vehicle, a bad signature) and "
      "every frame lost on the link; sends nothing to the vehicle unless --request-rate asks."};
  app.add_option("--field", bridge.fields,
                 "a field to publish, as MESSAGE.field (ATTITUDE.pitchspeed), "
                 "MESSAGE.field[i] (ACTUATOR_OUTPUT_STATUS.actuator[1], from 0) or "
                 "MESSAGE@SYSID:COMPID.field when several vehicles share the link (repeatable or "
                 "comma-separated; odonata-log topics FILE.tlog lists a recording's)")
      ->required()
      ->delimiter(',');
  app.add_option("--udp", udp,
                 "[ADDRESS:]PORT to listen on for datagrams, as a ground station does (PX4 and "
                 "ArduPilot SITL send to 14550)")
      ->capture_default_str();
  bool stamped = false;
  app.add_flag("--udp-stamped", stamped,
               "each datagram is one .tlog record (an 8-byte big-endian microsecond stamp, then "
               "the frame), timed by its stamp rather than its arrival: a recording replayed "
               "with its own times, read as odonata-fit reads the .tlog");
  app.add_option("--serial", o.link.serial_device,
                 "read a serial port instead (a telemetry radio: /dev/ttyUSB0)");
  app.add_option("--baud", o.link.baud, "the serial port's baud rate")
      ->capture_default_str()
      ->check(CLI::Range(50u, 12000000u));
  app.add_option("--rate", bridge.rate_hz,
                 "the grid's rate, Hz (default: the slowest named field's median rate over its "
                 "first 2 s, said on stderr)")
      ->check(CLI::Range(1e-3, 1e5));
  app.add_option("--max-gap", bridge.max_gap,
                 "grid samples a field's missing frames may span and still be interpolated; "
                 "longer, the samples are gaps (not sent, counted)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  app.add_option("--silence", bridge.silence_s,
                 "seconds after which a named field not heard is warned about")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--request-rate", requests,
                 "ask the vehicle to send MESSAGE at HZ (MESSAGE=HZ, e.g. ATTITUDE=100; "
                 "repeatable): the standard MAV_CMD_SET_MESSAGE_INTERVAL, sent once the vehicle "
                 "is heard and repeated until it answers (3 tries)");
  app.add_option("--target", target, "SYSID:COMPID that --request-rate asks")
      ->capture_default_str();
  app.add_option("--signing-key", key_path,
                 "the link's MAVLink 2 signing key (a file of 64 hex digits; from a passphrase: "
                 "printf %s PASS | sha256sum): signed frames are checked with it, unsigned "
                 "frames dropped, both counted, and --request-rate's commands signed with it");
  app.add_option("--source", o.source, "signals_t.source, the vehicle's name")
      ->capture_default_str();
  app.add_option("--summary-json", summary_json,
                 "on exit, write the counts, the grid and each field's frames here");
  odonata::cli::AddBusOptions(&app, &bus_options, {"instance name", false});
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  try {
    if (!o.link.serial_device.empty()) {
      if (app.count("--udp") > 0) throw std::runtime_error("give --udp or --serial, not both");
      if (stamped) throw std::runtime_error("--udp-stamped is for --udp, not --serial");
      o.link.kind = odonata::mavlink_service::LinkKind::kSerial;
    } else {
      ParseUdp(udp, o.link);
      if (stamped) o.link.datagrams = odonata::mavlink_service::DatagramFormat::kTlogRecord;
    }
    ParseTarget(target, o);
    for (const std::string& r : requests)
      o.requests.push_back(odonata::mavlink::ParseRateRequest(r));
    if (!key_path.empty()) {
      o.signing_key = odonata::mavlink::ReadLinkKey(key_path);
      bridge.signature_check = odonata::mavlink::SignatureCheckFor(*o.signing_key);
      bridge.unsigned_frames = odonata::mavlink::UnsignedFrames::kRefuse;
    }
    odonata::bus::BusNode bus(bus_options.ToBusOptions("odonata-mavlink"));
    odonata::mavlink_service::MavlinkNode node(bus, std::move(bridge), o);
    const int code = bus.Run();
    std::printf("odonata-mavlink: %s\n", node.SummaryLine().c_str());
    if (!summary_json.empty())
      odonata::io::WriteFileAtomically(summary_json, node.Summary().dump(1) + "\n");
    return code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-mavlink: error: %s\n", e.what());
    return 1;
  }
}
