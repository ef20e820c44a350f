// odonata-monitor: live accuracy of the online identifier, and the health of every service.

#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus_cli/bus_options.hpp"
#include "cli/parse_command_line.hpp"
#include "monitor_node.hpp"

int main(int argc, char** argv) {
  odonata::monitor::MonitorOptions o;
  odonata::cli::BusCliOptions bus_options;
  bus_options.instance = "monitor";
  CLI::App app{
      "Scores ODONATA_PREDICTION over a sliding window and since start, publishes "
      "ODONATA_ACCURACY, shows a live table, warns on low accuracy or silent services, "
      "and keeps each identifier's last model snapshot for a restart."};
  app.add_option("--window", o.scoring.window_samples, "sliding window, samples")
      ->capture_default_str();
  app.add_option("--publish-hz", o.publish_hz, "ODONATA_ACCURACY rate")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--print-period", o.print_period_s,
                 "seconds between table prints when not on a terminal")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--alarm-window", o.scoring.alarm_window_samples,
                 "change alarm: samples in its window, one second of data (100 at 100 Hz)")
      ->capture_default_str()
      ->check(CLI::Range(5, 100000));
  app.add_option("--alarm-drop", o.scoring.alarm_drop_points,
                 "change alarm: raise it when the tracking FIT falls this many points below its "
                 "settled level (and clear it within 1 point of that level)")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 100.0));
  app.add_option("--arx-margin", o.scoring.arx_margin_points,
                 "the fuzzy model is behind the identifier's live ARX while its window one-step "
                 "FIT is not above the ARX's, and ahead again when it leads by more than this "
                 "many points")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--warn-fit", o.scoring.warn_fit_percent, "warn below this window FIT %")
      ->capture_default_str();
  app.add_option("--heartbeat-timeout", o.heartbeat_timeout_s,
                 "seconds of silence before a warning")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--summary-json", o.summary_json, "write the final accuracy here on exit");
  odonata::cli::AddBusOptions(&app, &bus_options);
  // Any option can also come from a settings file (TOML/INI, option names as keys).
  app.set_config("--settings", "", "read options from this TOML/INI file");
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  try {
    o.live_table = isatty(STDOUT_FILENO) == 1;
    odonata::bus::BusOptions opts = bus_options.ToBusOptions("odonata-monitor");
    odonata::bus::BusNode bus(opts);
    odonata::monitor::MonitorNode node(bus, o);
    return bus.Run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-monitor: error: %s\n", e.what());
    return 1;
  }
}
