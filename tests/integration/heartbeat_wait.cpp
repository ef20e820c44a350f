// heartbeat_wait: the integration tests' way to wait for the system itself instead of the clock.
// Exits 0 once every named instance has published a heartbeat (ODONATA_HEARTBEAT) that meets the
// conditions — in one of the given states, with a counter at least N, published after this tool
// started when --fresh — and 1 at the timeout, naming what it waited for and what it last saw.
//
//   heartbeat_wait --lcm-url URL --instance ident --instance logger --state running
//   heartbeat_wait --lcm-url URL --instance ident --at-least messages_in=600 --timeout 30

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus/bus_node.hpp"
#include "bus_cli/channel_options.hpp"
#include "odonata/heartbeat_t.hpp"

namespace {

int64_t Counter(const odonata::heartbeat_t& hb, const std::string& name) {
  if (name == "messages_in") return hb.messages_in;
  if (name == "messages_out") return hb.messages_out;
  if (name == "decode_errors") return hb.decode_errors;
  if (name == "dropped") return hb.dropped;
  if (name == "gaps") return hb.gaps;
  if (name == "seq") return hb.seq;
  throw std::invalid_argument("unknown counter '" + name + "'");
}

}  // namespace

int main(int argc, char** argv) {
  std::string lcm_url, at_least;
  std::vector<std::string> instances, states;
  double timeout_s = 30;
  bool fresh = false;
  CLI::App app{"Waits for heartbeats of the named instances that meet every condition."};
  app.add_option("--lcm-url", lcm_url, "LCM URL");
  app.add_option("--instance", instances, "instance (or service) name, repeatable")->required();
  app.add_option("--state", states, "accepted heartbeat states (default: any), repeatable");
  app.add_option("--at-least", at_least,
                 "COUNTER=N: messages_in, messages_out, decode_errors, dropped, gaps or seq");
  app.add_flag("--fresh", fresh, "only heartbeats published after this tool started");
  app.add_option("--timeout", timeout_s, "seconds before giving up")->check(CLI::PositiveNumber);
  odonata::cli::ChannelOptions channels;
  odonata::cli::AddChannelOptions(&app, &channels);
  CLI11_PARSE(app, argc, argv);

  std::string counter;
  int64_t minimum = 0;
  if (!at_least.empty()) {
    const auto eq = at_least.find('=');
    if (eq == std::string::npos) {
      std::fprintf(stderr, "heartbeat_wait: --at-least takes COUNTER=N\n");
      return 2;
    }
    counter = at_least.substr(0, eq);
    minimum = std::stoll(at_least.substr(eq + 1));
  }
  try {
    odonata::bus::BusOptions o;
    o.lcm_url = lcm_url;
    o.service = "heartbeat_wait";
    o.heartbeat_period_s = 0;
    channels.ApplyTo(&o.channels);
    odonata::bus::BusNode bus(o);
    const int64_t started = odonata::bus::NowUtime();
    std::set<std::string> pending(instances.begin(), instances.end());
    std::map<std::string, std::string> last_seen;
    bus.Subscribe<odonata::heartbeat_t>(
        bus.channels().heartbeat, [&](const odonata::heartbeat_t& hb) {
          const std::string name = pending.count(hb.instance) ? hb.instance : hb.service;
          if (!pending.count(name)) return;
          last_seen[name] = "state " + hb.state + ", messages_in " +
                            std::to_string(hb.messages_in) + ", messages_out " +
                            std::to_string(hb.messages_out) + ", dropped " +
                            std::to_string(hb.dropped) + ", decode_errors " +
                            std::to_string(hb.decode_errors) + ", gaps " + std::to_string(hb.gaps);
          if (fresh && hb.utime < started) return;
          if (!states.empty() && std::find(states.begin(), states.end(), hb.state) == states.end())
            return;
          if (!counter.empty() && Counter(hb, counter) < minimum) return;
          pending.erase(name);
          std::printf("%s: %s\n", name.c_str(), last_seen[name].c_str());
          if (pending.empty()) bus.Stop(0);
        });
    bus.After(std::chrono::microseconds(static_cast<int64_t>(timeout_s * 1e6)), [&] {
      std::string what;
      for (const auto& name : pending) {
        what += " " + name +
                " (last seen: " + (last_seen.count(name) ? last_seen[name] : std::string("never")) +
                ")";
      }
      std::fprintf(stderr, "heartbeat_wait: no heartbeat within %.3g s%s%s%s%s from:%s\n",
                   timeout_s, states.empty() ? "" : " in the state asked",
                   counter.empty() ? "" : " with ", at_least.c_str(), fresh ? " (fresh)" : "",
                   what.c_str());
      bus.Stop(1);
    });
    return bus.Run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "heartbeat_wait: error: %s\n", e.what());
    return 2;
  }
}
