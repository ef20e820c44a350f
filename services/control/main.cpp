// odonata-control: sends one operator command (control_t) to the running services and prints
// their answers (control_reply_t); exits non-zero when one rejects it or none answers.

#include <chrono>
#include <cstdio>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus/bus_node.hpp"
#include "bus/control_gate.hpp"
#include "bus_cli/channel_options.hpp"
#include "cli/parse_command_line.hpp"
#include "odonata/control_reply_t.hpp"
#include "odonata/control_t.hpp"

namespace {

constexpr int kExitRejected = 1;
constexpr int kExitNoAnswer = 3;
constexpr std::chrono::milliseconds kResend{250};

bool TakesValue(int8_t c) {
  return c == odonata::control_t::SET_ENTROPY_THRESHOLD || c == odonata::control_t::SET_FORGETTING;
}

// A sequence number no earlier run of this tool is likely to have used, so replies to another
// odonata-control (or to an earlier run of this one) are told apart.
int64_t FreshSeq() {
  std::random_device rd;
  const uint64_t r =
      (uint64_t{rd()} << 32) ^ rd() ^ static_cast<uint64_t>(odonata::bus::NowUtime());
  return static_cast<int64_t>(r >> 1) | 1;
}

void Print(const odonata::control_reply_t& r) {
  std::printf("%s (%s): %s: %s", r.instance.c_str(), r.service.c_str(),
              r.accepted ? "accepted" : "REJECTED", r.reason.c_str());
  for (int i = 0; i < r.num_params; ++i)
    std::printf("%s %s=%.10g", i == 0 ? "\n   " : "", r.names[static_cast<std::size_t>(i)].c_str(),
                r.values[static_cast<std::size_t>(i)]);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  const auto& commands = odonata::bus::ControlCommands();
  std::string command, argument, target, path, lcm_url, sender = "odonata-control";
  double value = 0, timeout_s = 1.0;
  bool value_given = false;
  CLI::App app{
      "Sends a command to odonata services on ODONATA_CONTROL and prints every answer "
      "(ODONATA_CONTROL_REPLY): reset, freeze, resume, set-entropy-threshold H, set-forgetting "
      "LAMBDA, save-model [NAME], publish-snapshot, get (the live parameters), shutdown. Exits 0 "
      "when every answer accepts, 1 when one rejects, 3 when no service answers."};
  app.add_option("command", command, "what to do")->required()->check(CLI::IsMember(commands));
  app.add_option("argument", argument,
                 "set-entropy-threshold / set-forgetting: the value; save-model: the file name; "
                 "reset of the plant: a preset");
  app.add_option("--target", target,
                 "instance or service name (default: every service; each one that acts answers)");
  auto* value_opt = app.add_option("--value", value, "the value (same as the argument)");
  app.add_option("--path", path, "the file name or preset (same as the argument)");
  app.add_option("--timeout", timeout_s, "seconds to collect answers")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 60.0));
  app.add_option("--lcm-url", lcm_url, "LCM URL (default: LCM_DEFAULT_URL or udpm ttl=0)");
  odonata::cli::ChannelOptions channels;
  odonata::cli::AddChannelOptions(&app, &channels);
  app.add_option("--instance", sender,
                 "sender name; services obey reset and shutdown only from the names in their "
                 "--control-from")
      ->capture_default_str();
  // Like every service: a board's settings file can name the bus and the sender.
  app.set_config("--settings", "", "read options from this TOML/INI file");
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;

  const int8_t code = commands.at(command);
  value_given = value_opt->count() > 0;
  if (!argument.empty()) {
    if (TakesValue(code)) {
      try {
        std::size_t used = 0;
        value = std::stod(argument, &used);
        if (used != argument.size()) throw std::invalid_argument(argument);
      } catch (const std::exception&) {
        std::fprintf(stderr, "odonata-control: %s needs a number, not '%s'\n", command.c_str(),
                     argument.c_str());
        return 2;
      }
      value_given = true;
    } else if (code == odonata::control_t::SAVE_MODEL || code == odonata::control_t::RESET) {
      path = argument;
    } else {
      std::fprintf(stderr, "odonata-control: %s takes no argument (got '%s')\n", command.c_str(),
                   argument.c_str());
      return 2;
    }
  }
  if (TakesValue(code) && !value_given) {
    std::fprintf(stderr, "odonata-control: %s needs a value: odonata-control %s VALUE\n",
                 command.c_str(), command.c_str());
    return 2;
  }

  try {
    odonata::bus::BusOptions o;
    o.lcm_url = lcm_url;
    o.key_path = channels.key_path;
    o.service = "odonata-control";
    o.instance = sender;
    o.heartbeat_period_s = 0;
    o.one_shot = true;  // not a peer to watch
    channels.ApplyTo(&o.channels);
    odonata::bus::BusNode bus(o);

    odonata::control_t msg{};
    msg.utime = odonata::bus::NowUtime();
    msg.seq = FreshSeq();
    msg.sender = sender;
    msg.target = target;
    msg.command = code;
    msg.value = value;
    msg.path = path;

    // A lost command or answer is repaired by sending the same message again every kResend until
    // the timeout: a service that already answered it answers again without obeying twice
    // (BusNode::AcceptControl), and each service's first answer is the one counted.
    std::set<std::string> answered;
    int rejected = 0;
    bool done = false;
    bus.Subscribe<odonata::control_reply_t>(
        bus.channels().control_reply, [&](const odonata::control_reply_t& r) {
          if (r.request_sender != msg.sender || r.request_seq != msg.seq) return;
          if (!answered.insert(r.instance).second) return;
          Print(r);
          std::fflush(stdout);
          if (!r.accepted) ++rejected;
          // An instance named as the target answers once: no need to wait any longer.
          if (!target.empty() && r.instance == target) {
            done = true;
            bus.Stop(0);
          }
        });
    const auto send = [&] {
      if (!bus.Publish(bus.channels().control, msg))
        std::fprintf(stderr, "odonata-control: warning: publish failed\n");
    };
    send();
    bus.Every(kResend, [&] {
      // Broadcasts go on until the timeout: who else will answer is not known.
      if (!done && (target.empty() || answered.empty())) send();
    });
    bus.After(std::chrono::microseconds(static_cast<int64_t>(timeout_s * 1e6)),
              [&bus] { bus.Stop(0); });
    bus.Run();
    if (answered.empty()) {
      std::fprintf(stderr,
                   "odonata-control: no answer to %s within %.2g s%s: is the service running on "
                   "this bus, and is the name right?\n",
                   command.c_str(), timeout_s,
                   target.empty() ? "" : (" from '" + target + "'").c_str());
      return kExitNoAnswer;
    }
    // Without the key nothing proves who answered: anyone on the bus can send a reply.
    if (channels.key_path.empty())
      std::fprintf(stderr,
                   "odonata-control: note: without --key these answers are not authenticated "
                   "(anyone on the bus could have sent them); on a signed system give the key\n");
    return rejected > 0 ? kExitRejected : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-control: error: %s\n", e.what());
    return 1;
  }
}
