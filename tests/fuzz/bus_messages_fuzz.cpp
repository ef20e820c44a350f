// Fuzz harness: every message's decode-and-handle path. The first byte picks a channel, the rest
// is published as the message's bytes on an in-process bus (memq://) where a lockstep plant, two
// identifiers (the DI-MAV's messages, and any vehicle's signals_t), a monitor and a logger
// listen, as they do on the real bus: decode, validate and handle. Nothing may crash; bad input
// is counted (decode errors, dropped).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bus/bus_node.hpp"
#include "identifier_config/identifier_config.hpp"
#include "identifier_node.hpp"
#include "logger_node.hpp"
#include "monitor_node.hpp"
#include "plant/plant_config.hpp"
#include "plant_node.hpp"

namespace {

struct Harness {
  std::string dir;
  std::unique_ptr<odonata::bus::BusNode> bus;
  std::unique_ptr<odonata::plant_service::PlantNode> plant;
  std::unique_ptr<odonata::identifier::IdentifierNode> identifier;
  std::unique_ptr<odonata::identifier::IdentifierNode> signals_identifier;  // any vehicle's
  std::unique_ptr<odonata::monitor::MonitorNode> monitor;
  std::unique_ptr<odonata::logger::LoggerNode> logger;
  std::vector<std::string> channels;

  Harness() {
    char tmpl[] = "/tmp/odonata_fuzz_bus_XXXXXX";
    dir = mkdtemp(tmpl) ? tmpl : "/tmp";
    odonata::bus::BusOptions o;
    o.lcm_url = "memq://";
    o.service = "fuzz";
    o.instance = "identifier";  // so control messages addressed to it reach the identifier
    o.heartbeat_period_s = 0;
    bus = std::make_unique<odonata::bus::BusNode>(o);
    plant = std::make_unique<odonata::plant_service::PlantNode>(
        *bus, odonata::plant::DefaultPlantConfig(),
        odonata::pipeline::PlantSession::Mode::kLockstep, "roll");
    odonata::identifier::IdentifierConfig config = odonata::identifier::DefaultIdentifierConfig();
    config.resume_wait_s = 0;
    config.snapshot_period_s = 0;
    identifier =
        std::make_unique<odonata::identifier::IdentifierNode>(*bus, config, std::nullopt, "", dir);
    odonata::identifier::IdentifierConfig any = config;
    any.instance = "identifier-signals";
    any.source = odonata::identifier::SampleSource::kSignals;
    signals_identifier =
        std::make_unique<odonata::identifier::IdentifierNode>(*bus, any, std::nullopt, "", dir);
    odonata::monitor::MonitorOptions mo;
    mo.print_period_s = 1e9;
    monitor = std::make_unique<odonata::monitor::MonitorNode>(*bus, mo);
    odonata::logger::RecordOptions ro;
    ro.prefix = dir + "/log";
    ro.split_bytes = 1 << 20;
    logger = std::make_unique<odonata::logger::LoggerNode>(*bus, ro);
    const auto& c = bus->channels();
    channels = {c.command,  c.state,     c.beat_state, c.prediction, c.model,
                c.accuracy, c.heartbeat, c.control,    c.ack,        c.signals};
  }
  ~Harness() {
    logger.reset();
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Harness h;
  if (size == 0) return 0;
  const std::string& channel = h.channels[data[0] % h.channels.size()];
  if (channel == h.bus->channels().control) {
    // A shutdown would end the loop for every later input: everything else is fuzzed.
    odonata::control_t c;
    if (odonata::bus::SafeDecode(&c, data + 1, static_cast<int64_t>(size - 1)) &&
        c.command == odonata::control_t::SHUTDOWN)
      return 0;
  }
  h.bus->lcm().publish(channel, data + 1, static_cast<unsigned>(size - 1));
  h.bus->io().restart();
  h.bus->io().poll();
  return 0;
}
