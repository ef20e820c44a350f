// odonata-fit (and odonata-identifier) run as real processes from a GoogleTest suite: the helpers
// fit_cli_test.cpp and fit_cli_selection_test.cpp share.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace odonata::fit_process {

struct ProcessResult {
  int status = -1;
  std::string out;  // stdout and stderr together
};

inline ProcessResult Exec(const std::string& args, bool merge_stderr = true, bool raw = false) {
  // raw: `args` is the whole shell command (its own program and redirections).
  const std::string cmd =
      raw ? args
          : std::string(ODONATA_FIT_EXE) + " " + args + (merge_stderr ? " 2>&1" : " 2>/dev/null");
  ProcessResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  return r;
}

inline std::string Dir() { return ::testing::TempDir(); }

inline std::string Write(const std::string& name, const std::string& text) {
  const std::string path = Dir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

inline std::string Example(const std::string& f) {
  return std::string(ODONATA_EXAMPLES_DIR) + "/narendra/" + f;
}

// The example's first `rows` training rows, in a file of the running test's own (ctest runs the
// tests as parallel processes over the same folder).
inline std::string TrainHead(int rows) {
  const std::string path = Dir() + "/narendra_train_" + std::to_string(rows) + "_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".csv";
  std::ifstream in(Example("train.csv"));
  std::ofstream out(path);
  std::string line;
  for (int k = 0; k <= rows && std::getline(in, line); ++k) out << line << "\n";
  return path;
}

// 1000 rows: enough for a selection with a hold-out and folds, and a fifth of the full file's
// cost for the tests about the CLI's contract rather than its accuracy (each whole-file selection
// took 1–2 minutes under the sanitizers).
inline std::string ShortTrain() { return TrainHead(1000); }

/// The first `n` numbers of a line of a predictions file (comma-separated).
inline std::vector<double> CsvNumbers(const std::string& line, int n) {
  std::vector<double> v;
  std::size_t pos = 0;
  for (int c = 0; c < n; ++c) {
    const std::size_t next = line.find(',', pos);
    v.push_back(std::stod(line.substr(pos, next - pos)));
    pos = next + 1;
  }
  return v;
}

}  // namespace odonata::fit_process
