#pragma once
// One exit-code convention for every odonata program: 0 after --help, 2 for bad arguments.

#include <optional>

#include <CLI/CLI.hpp>

namespace odonata::cli {

/// Parses the command line. Returns the code to exit with now (0 after --help, 2 for bad
/// arguments, CLI11 having printed why), or nullopt when the program should go on.
inline std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return std::nullopt;
}

}  // namespace odonata::cli
