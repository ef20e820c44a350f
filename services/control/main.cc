// odonata-control: sends one operator command (control_t) to the running services.

#include <cstdio>
#include <map>

#include <CLI/CLI.hpp>

#include <lcm/lcm-cpp.hpp>
#include "bus/bus_node.hpp"
#include "cli/parse_command_line.hpp"
#include "odonata/control_t.hpp"

int main(int argc, char** argv) {
  const std::map<std::string, int8_t> commands = {
      {"reset", odonata::control_t::RESET},
      {"freeze", odonata::control_t::FREEZE},
      {"resume", odonata::control_t::RESUME},
      {"set-entropy-threshold", odonata::control_t::SET_ENTROPY_THRESHOLD},
      {"set-forgetting", odonata::control_t::SET_FORGETTING},
      {"save-model", odonata::control_t::SAVE_MODEL},
      {"publish-snapshot", odonata::control_t::PUBLISH_SNAPSHOT},
      {"shutdown", odonata::control_t::SHUTDOWN}};
  std::string command, target, path, lcm_url, channel = "ODONATA_CONTROL",
                                              sender = "odonata-control";
  double value = 0;
  CLI::App app{
      "Sends a command to odonata services on ODONATA_CONTROL: reset, freeze, resume, "
      "set-entropy-threshold --value H, set-forgetting --value LAMBDA, save-model [--path FILE], "
      "publish-snapshot, shutdown."};
  app.add_option("command", command, "what to do")->required()->transform(CLI::IsMember(commands));
  app.add_option("--target", target, "instance or service name (default: every service)");
  app.add_option(
      "--value", value,
      "the new entropy threshold (set-entropy-threshold) or forgetting factor (set-forgetting)");
  app.add_option("--path", path,
                 "save-model: a plain file name, written in the identifier's --models-dir "
                 "(default: its --save-model file); reset of the plant: a preset");
  app.add_option("--lcm-url", lcm_url, "LCM URL (default: LCM_DEFAULT_URL or udpm ttl=0)");
  app.add_option("--channel", channel, "control channel")->capture_default_str();
  app.add_option("--instance", sender,
                 "sender name; services obey reset and shutdown only from the names in their "
                 "--control-from")
      ->capture_default_str();
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  lcm::LCM lcm(lcm_url);
  if (!lcm.good()) {
    std::fprintf(stderr, "odonata-control: error: cannot open LCM (is there a multicast route?)\n");
    return 1;
  }
  odonata::control_t msg{};
  msg.utime = odonata::bus::NowUtime();
  msg.seq = 0;
  msg.sender = sender;
  msg.target = target;
  msg.command = commands.at(command);
  msg.value = value;
  msg.path = path;
  if (lcm.publish(channel, &msg) != 0) {
    std::fprintf(stderr, "odonata-control: error: publish failed\n");
    return 1;
  }
  return 0;
}
