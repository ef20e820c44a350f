// odonata-fit: fit an entropy fuzzy NARX model offline on CSV files and report its accuracy.

#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/parse_command_line.hpp"
#include "fit/fit_job.hpp"
#include "fit/fit_report_text.hpp"
#include "fit_cli.hpp"

int main(int argc, char** argv) {
  odonata::fit::FitJobOptions o;
  odonata::fit::FitCli c;
  CLI::App app{
      "Fits an entropy fuzzy model (series-parallel NARX) on CSV data: header row, one sample per "
      "row. Settings not given (consequent, entropy threshold, kappa, epochs) are chosen on the "
      "last part of the training file by simulation accuracy; the validation file is only "
      "scored. Reports FIT/VAF/RMSE one-step and free-run, beside linear ARX and persistence."};
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
    const auto report = odonata::fit::RunFitJob(o);
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
  } catch (const std::exception& e) {
    std::cerr << "odonata-fit: error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
