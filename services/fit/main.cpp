// odonata-fit: fit an entropy fuzzy NARX model offline on CSV files and report its accuracy.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/parse_command_line.hpp"
#include "fit/fit_job.hpp"
#include "fit/fit_plot_data.hpp"
#include "fit/fit_report_text.hpp"
#include "fit_cli.hpp"
#include "sysid/model/nothing_to_identify.hpp"

namespace {

// The command, shell-quoted, as the page shows it for reproducing the fit.
std::string QuotedCommand(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    const std::string a = i == 0 ? "odonata-fit" : argv[i];
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMN"
                                         "OPQRSTUVWXYZ0123456789-_./=:,+@%") == std::string::npos;
    std::string quoted = "'";
    for (const char ch : a) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    line += (i ? " " : "") + (plain ? a : quoted + "'");
  }
  return line;
}

// --report: the command beside what the fit wrote, then the page.
std::string WriteReport(const std::string& dir, int argc, char** argv) {
  std::ofstream out(std::filesystem::path(dir) / "command.txt");
  out << QuotedCommand(argc, argv) << "\n";
  out.close();
  if (!out) throw std::runtime_error(dir + "/command.txt: cannot write");
  return odonata::fit::WriteReportPage(dir);
}

}  // namespace

int main(int argc, char** argv) {
  odonata::fit::FitJobOptions o;
  odonata::fit::FitCli c;
  CLI::App app{
      "Fits an entropy fuzzy model (series-parallel NARX) on CSV data: header row, one sample per "
      "row. Settings not given (consequent, entropy threshold, kappa, epochs) are chosen on the "
      "last part of the training file by simulation accuracy; the validation file is only "
      "scored. Reports FIT/VAF/RMSE one-step and free-run, beside linear ARX and persistence."};
  app.footer(
      "Exit status: 0 a model was fitted; 1 an error (a file, an option, a write); 2 a usage "
      "mistake; 3 nothing to identify: the data cannot give a meaningful model (a signal that "
      "never moves, too short for the lags, a window that keeps nothing), said with what to do. "
      "Time with the defaults on two cores (2026-12-02): about 5 s for 5 000 rows, 9 s for "
      "10 000, 16 s for 65 000, 20 s for 100 000, 26 s for 360 000; the search is most of it, "
      "and the progress bar estimates each phase's rest (docs/reference/benchmarks.md).");
  odonata::fit::AddFitOptions(&app, c, &o);
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  if (const auto format = c.csv_format.Format()) {
    o.csv_format = *format;
  } else {
    std::fprintf(stderr, "odonata-fit: --decimal ',' needs another --delimiter (';' or tab)\n");
    return 2;
  }
  try {
    odonata::fit::ApplyFitCli(c, o);
    o.note = [](const std::string& note) { std::cerr << "odonata-fit: " << note << "\n"; };
    if (!c.report_dir.empty()) std::filesystem::create_directories(c.report_dir);
    auto report = odonata::fit::RunFitJob(o);
    if (!c.report_dir.empty()) {
      report["report_page"] = WriteReport(c.report_dir, argc, argv);
      std::cerr << "odonata-fit: report written to " << report["report_page"].get<std::string>()
                << "\n";
    }
    if (c.json) {
      std::cout << report.dump(1) << std::endl;
      for (const auto& w : report["warnings"])
        std::cerr << "odonata-fit: warning: " << w.get<std::string>() << "\n";
    } else {
      std::cout << odonata::fit::FormatReport(report, c.full_rules ? odonata::fit::RulesShown::kFull
                                                      : c.rules
                                                          ? odonata::fit::RulesShown::kReadable
                                                          : odonata::fit::RulesShown::kNone);
    }
    // A model that came out a constant has identified nothing: the outputs are written (to be
    // looked at), but the run is no success (issue 57).
    const nlohmann::json flags = report.contains("verdict")
                                     ? report["verdict"].value("flags", nlohmann::json::array())
                                     : nlohmann::json::array();
    if (std::find(flags.begin(), flags.end(), "constant") != flags.end()) {
      std::cerr << "odonata-fit: nothing to identify: the model is a constant ("
                << report["verdict"]["text"].get<std::string>()
                << "); the data does not show the output answering the inputs\n";
      return odonata::sysid::kNothingToIdentifyExit;
    }
  } catch (const odonata::sysid::NothingToIdentify& e) {
    std::cerr << "odonata-fit: nothing to identify: " << e.what() << std::endl;
    return odonata::sysid::kNothingToIdentifyExit;
  } catch (const std::exception& e) {
    std::cerr << "odonata-fit: error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
