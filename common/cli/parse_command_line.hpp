#pragma once
// One command-line convention for every odonata program: 0 after --help and --version, 2 for bad
// arguments, and a mistyped option answered with the closest one it may have meant.

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#ifndef ODONATA_VERSION
#define ODONATA_VERSION "unknown"
#endif

namespace odonata::cli {

/// Edit distance (insertions, deletions, substitutions, adjacent swaps) between two words.
inline std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min(
          {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

/// The `most` names of `candidates` closest to `name` by EditDistance, closest first (ties in
/// alphabetical order): the "nearest: …" every reader of a log answers a mistyped name with.
/// `name_of` gives a candidate's name.
template <class Range, class NameOf>
std::vector<std::string> NearestNames(const std::string& name, const Range& candidates,
                                      NameOf name_of, std::size_t most = 5) {
  std::vector<std::pair<std::size_t, const std::string*>> near;
  for (const auto& c : candidates) {
    const std::string& n = name_of(c);
    near.emplace_back(EditDistance(name, n), &n);
  }
  const std::size_t shown = std::min(most, near.size());
  std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(shown), near.end(),
                    [](const auto& a, const auto& b) {
                      return a.first != b.first ? a.first < b.first : *a.second < *b.second;
                    });
  std::vector<std::string> out;
  for (std::size_t i = 0; i < shown; ++i) out.push_back(*near[i].second);
  return out;
}

/// "a, b, c".
inline std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// The long options of `app` and of its subcommands, without their dashes.
inline std::vector<std::string> LongOptionNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_options())
    for (const auto& n : o->get_lnames()) names.push_back(n);
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    for (const auto& n : LongOptionNames(*sub)) names.push_back(n);
  return names;
}

/// For each --word on the command line that is no option: "did you mean --X?" when one is close
/// (within a third of its length, at least one edit).
inline void SuggestCloseOptions(const CLI::App& app, int argc, char** argv) {
  const std::vector<std::string> known = LongOptionNames(app);
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0 || arg.size() < 3) continue;
    const std::string name =
        arg.substr(2, arg.find('=') == std::string::npos ? std::string::npos : arg.find('=') - 2);
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::string best;
    std::size_t best_d = std::max<std::size_t>(1, name.size() / 3) + 1;
    for (const auto& k : known) {
      const std::size_t d = EditDistance(name, k);
      if (d < best_d) best_d = d, best = k;
    }
    if (!best.empty())
      std::fprintf(stderr, "--%s: did you mean --%s?\n", name.c_str(), best.c_str());
  }
}

/// Parses the command line. Returns the code to exit with now (0 after --help or --version, 2
/// for bad arguments, CLI11 having printed why), or nullopt when the program should go on.
inline std::optional<int> ParseCommandLine(CLI::App& app, int argc, char** argv) {
  std::string program = argc > 0 ? argv[0] : "odonata";
  program = program.substr(program.find_last_of('/') + 1);
  app.set_version_flag("--version", program + " (odonata) " ODONATA_VERSION);
  // Subcommands' options too (odonata-logger record/export): what the man pages are made of.
  if (!app.get_subcommands([](const CLI::App*) { return true; }).empty())
    app.set_help_all_flag("--help-all", "Print this help message and every subcommand's, and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    if (code != 0) SuggestCloseOptions(app, argc, argv);
    return code == 0 ? 0 : 2;
  }
  return std::nullopt;
}

}  // namespace odonata::cli
