// odonata-fit run as a real process: its JSON contract and every bad-input case of issue 2.

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fit_process.hpp"

namespace {

using namespace odonata::fit_process;

TEST(FitCli, HelpDescribesTheContract) {
  const ProcessResult r = Exec("--help");
  EXPECT_EQ(r.status, 0);
  for (const char* flag :
       {"--train",       "--validate",   "--output",        "--input",
        "--ny",          "--nu",         "--delay",         "--entropy-threshold",
        "--max-rules",   "--epochs",     "--learning-rate", "--consequent",
        "--seed",        "--save-model", "--rules",         "--json",
        "--predictions", "--forgetting", "--no-select",     "--select-criterion",
        "--holdout"}) {
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  }
}

TEST(FitCli, JsonReportHasTheContractFields) {
  const ProcessResult r =
      Exec("--train " + Example("train.csv") + " --validate " + Example("validate.csv") +
               " --output y --input u --entropy-threshold 0.05 --kappa 1 "
               "--epochs 3 --consequent linear --json",
           false);
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["rules"].get<int>(), 0);
  EXPECT_DOUBLE_EQ(j["entropy_threshold"].get<double>(), 0.05);
  EXPECT_FALSE(j.contains("selection")) << "every setting was given: nothing to choose";
  EXPECT_TRUE(j["warnings"].is_array());
  for (const char* data : {"train", "validate"}) {
    for (const char* mode : {"one_step", "free_run"}) {
      for (const char* m : {"fit", "vaf", "rmse"})
        EXPECT_TRUE(j[data][mode][m].is_number()) << data << mode << m;
    }
  }
  for (const char* b : {"arx", "persistence"}) {
    for (const char* mode : {"one_step", "free_run"}) {
      for (const char* m : {"fit", "vaf", "rmse"})
        EXPECT_TRUE(j["baselines"][b]["validate"][mode][m].is_number()) << b << mode << m;
    }
  }
  // Persistence, recomputed here from the CSV: ŷ(k+1) = y(k) over k = 0 … N−2.
  std::ifstream csv(Example("validate.csv"));
  std::string line;
  std::getline(csv, line);
  ASSERT_EQ(line, "k,u,y");
  std::vector<double> y;
  while (std::getline(csv, line)) y.push_back(std::stod(line.substr(line.rfind(',') + 1)));
  ASSERT_GT(y.size(), 10u);
  double mean = 0, err = 0, dev = 0;
  for (std::size_t k = 1; k < y.size(); ++k) mean += y[k];
  mean /= static_cast<double>(y.size() - 1);
  for (std::size_t k = 1; k < y.size(); ++k) {
    err += (y[k] - y[k - 1]) * (y[k] - y[k - 1]);
    dev += (y[k] - mean) * (y[k] - mean);
  }
  EXPECT_NEAR(j["baselines"]["persistence"]["validate"]["one_step"]["fit"].get<double>(),
              100.0 * (1.0 - std::sqrt(err / dev)), 1e-9);
  EXPECT_NEAR(j["baselines"]["persistence"]["validate"]["one_step"]["rmse"].get<double>(),
              std::sqrt(err / static_cast<double>(y.size() - 1)), 1e-12);
}

TEST(FitCli, StaticRegressionHasNoFreeRun) {
  const ProcessResult r = Exec("--train " + Example("train.csv") +
                                   " --output y --input u --ny 0 --delay 0 --no-select --json",
                               false);
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["train"].contains("one_step"));
  EXPECT_FALSE(j["train"].contains("free_run"));
}

TEST(FitCli, SaveThenLoadReproducesTheValidationScores) {
  const std::string model = Dir() + "/cli-model.json";
  const std::string common = " --validate " + Example("validate.csv") + " --json";
  const ProcessResult a =
      Exec("--train " + Example("train.csv") +
               " --output y --input u --consequent linear --no-select --epochs 3 --save-model " +
               model + common,
           false);
  ASSERT_EQ(a.status, 0) << a.out;
  const ProcessResult b = Exec("--load-model " + model + common, false);
  ASSERT_EQ(b.status, 0) << b.out;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  EXPECT_EQ(ja["validate"], jb["validate"]);
  EXPECT_EQ(ja["rules"], jb["rules"]);
}

TEST(FitCli, SameSeedAndDataGiveTheSameModelFile) {
  const std::string m1 = Dir() + "/det1.json", m2 = Dir() + "/det2.json";
  const std::string args = "--train " + Example("train.csv") +
                           " --output y --input u --epochs 2 --no-select --seed 5 --save-model ";
  ASSERT_EQ(Exec(args + m1).status, 0);
  ASSERT_EQ(Exec(args + m2).status, 0);
  std::ifstream f1(m1), f2(m2);
  const std::string s1((std::istreambuf_iterator<char>(f1)), {}),
      s2((std::istreambuf_iterator<char>(f2)), {});
  EXPECT_FALSE(s1.empty());
  EXPECT_EQ(s1, s2);
}

TEST(FitCli, SelectionAndRulesAreReadable) {
  const ProcessResult r =
      Exec("--train " + Example("train.csv") + " --validate " + Example("validate.csv") +
           " --output y --input u --consequent singleton --select-kappas 1 "
           "--select-thresholds 0.3,0.45 --max-epochs 3 --rules");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("model selection on 1000 samples of the training file's end"),
            std::string::npos)
      << r.out;
  // The readable form by default: one clause per signal, named terms and their values.
  EXPECT_NE(r.out.find("rules, readable form"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("    IF y is "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("THEN y(k+1) is ≈"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  readable  "), std::string::npos) << "its scores beside the model's";
  EXPECT_EQ(r.out.find("\r"), std::string::npos) << "no progress bar when stderr is not a terminal";
  // Every rule of the full model on request.
  const ProcessResult full = Exec("--train " + Example("train.csv") +
                                  " --output y --input u --consequent singleton --select-kappas 1 "
                                  "--select-thresholds 0.45 --max-epochs 3 --full-rules");
  EXPECT_NE(full.out.find("1. IF y(k) is "), std::string::npos) << full.out;
}

// A training file longer than --search-rows is searched on blocks spread over it, which the
// report says (JSON and text), and the model is still trained on every row (issue 22).
TEST(FitCli, ALongFileIsSearchedOnBlocksAndTrainedWhole) {
  // Which rows the search and the final fit see is the point, not how the short list trains on
  // the simulation error (other tests): without it the three fits take a third of the time
  // under the sanitizers.
  const std::string common = "--train " + Example("train.csv") +
                             " --output y --input u --consequent linear --select-kappas 1 "
                             "--select-thresholds 0.3,0.45 --max-epochs 3 --simulation-steps 0";
  const std::string args = common + " --search-rows 2000";
  const ProcessResult j = Exec(args + " --json", false);
  ASSERT_EQ(j.status, 0) << j.out;
  const auto report = nlohmann::json::parse(j.out);
  EXPECT_EQ(report["selection"]["searched_rows"].get<long>(), 2000);
  EXPECT_EQ(report["selection"]["training_rows"].get<long>(), 5000);
  EXPECT_EQ(report["selection"]["fit_samples"].get<long>() +
                report["selection"]["holdout_samples"].get<long>(),
            2000);
  EXPECT_EQ(report["train"]["one_step"]["samples"].get<long>(), 4999) << "scored on every row";
  const ProcessResult t = Exec(args);
  ASSERT_EQ(t.status, 0) << t.out;
  EXPECT_NE(t.out.find("searched on 2000 of the 5000 training rows"), std::string::npos) << t.out;
  const ProcessResult whole = Exec(common + " --search-rows 0 --json", false);
  ASSERT_EQ(whole.status, 0) << whole.out;
  EXPECT_EQ(nlohmann::json::parse(whole.out)["selection"]["searched_rows"].get<long>(), 5000);
}

// A spreadsheet's CSV outside English locales: --delimiter ';' --decimal ',' (issue 23 point 7).
TEST(FitCli, SemicolonSeparatedFilesWithDecimalCommas) {
  std::string semi = "u;y\n", dot = "u,y\n";
  for (int k = 0; k < 200; ++k) {
    const double u = std::sin(0.1 * k), y = 2.5 * u * u;
    char a[96], b[96];
    std::snprintf(a, sizeof a, "%.6f;%.6f\n", u, y);
    std::snprintf(b, sizeof b, "%.6f,%.6f\n", u, y);
    std::string row = a;
    for (auto& ch : row)
      if (ch == '.') ch = ',';
    semi += row;
    dot += b;
  }
  const std::string sp = Write("semi.csv", semi), dp = Write("dot.csv", dot);
  const std::string args = " --output y --input u --ny 0 --nu 1 --delay 0 --no-select --json";
  const ProcessResult plain = Exec("--train " + sp + args, false);
  EXPECT_EQ(plain.status, 1);
  const ProcessResult hint = Exec("--train " + sp + args);
  EXPECT_NE(hint.out.find("--delimiter ';'"), std::string::npos) << hint.out;
  const ProcessResult read = Exec("--train " + sp + args + " --delimiter ';' --decimal ,", false);
  ASSERT_EQ(read.status, 0) << read.out;
  const ProcessResult same = Exec("--train " + dp + args, false);
  ASSERT_EQ(same.status, 0) << same.out;
  EXPECT_EQ(nlohmann::json::parse(read.out)["train"], nlohmann::json::parse(same.out)["train"]);
  EXPECT_EQ(Exec("--train " + sp + args + " --decimal ,").status, 2);  // ',' twice
}

TEST(FitCli, PredictionsFileHoldsMeasuredFuzzyAndArxInBothModes) {
  const std::string out = Dir() + "/pred.csv";
  const ProcessResult r =
      Exec("--train " + Example("train.csv") + " --validate " + Example("validate.csv") +
               " --output y --input u --entropy-threshold 0.45 --kappa 1 "
               "--epochs 2 --consequent linear --json --predictions " +
               out,
           false);
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  std::ifstream in(out);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "set,sample,measured,fuzzy_one_step,fuzzy_free_run,arx_one_step,arx_free_run");
  // Recompute the validation one-step FIT from the file: it must be the report's.
  std::vector<double> y, yh;
  long rows = 0;
  while (std::getline(in, line)) {
    ++rows;
    const std::vector<double> v = CsvNumbers(line, 7);
    if (v[0] == 1.0) {
      y.push_back(v[2]);
      yh.push_back(v[3]);
    }
  }
  EXPECT_EQ(rows, 4999 + 999);
  ASSERT_EQ(y.size(), 999u);
  double mean = 0, se = 0, sv = 0;
  for (double v : y) mean += v / double(y.size());
  for (std::size_t k = 0; k < y.size(); ++k) {
    se += (y[k] - yh[k]) * (y[k] - yh[k]);
    sv += (y[k] - mean) * (y[k] - mean);
  }
  EXPECT_NEAR(100 * (1 - std::sqrt(se / sv)), j["validate"]["one_step"]["fit"].get<double>(), 1e-6);
}

TEST(FitCli, TrackLearnsOnlineBesideAFrozenCopyAndArx) {
  // The validation file as a "changed vehicle": the online copy keeps learning on it.
  const std::string out = Dir() + "/track.csv";
  const ProcessResult r = Exec("--train " + Example("train.csv") +
                                   " --output y --input u --entropy-threshold 0.45 --kappa 0.5 "
                                   "--epochs 1 --no-least-squares --consequent linear "
                                   "--forgetting 0.995 --json --track " +
                                   Example("validate.csv") + " --track-output " + out,
                               false);
  ASSERT_EQ(r.status, 0) << r.out;
  const auto t = nlohmann::json::parse(r.out)["track"];
  EXPECT_EQ(t["samples"].get<int>(), 999);
  for (const char* m : {"online", "frozen", "arx"}) {
    EXPECT_TRUE(t[m]["one_step"]["fit"].is_number()) << m;
    EXPECT_TRUE(t[m]["events"].is_array()) << m;
  }
  EXPECT_GT(t["online"]["one_step"]["fit"].get<double>(),
            t["frozen"]["one_step"]["fit"].get<double>())
      << "learning on the new data beats the frozen copy on it";
  std::ifstream in(out);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header,
            "sample,measured,online,frozen,arx,online_window_fit,frozen_window_fit,arx_window_fit");
}

TEST(FitCli, ProgressBarOnlyOnATerminal) {
  // script(1) gives the program a pseudo-terminal, as a user's shell would; a quiet time of 0
  // makes this short fit "long" (a fit under 2 s shows no bar).
  const std::string fit = "env ODONATA_PROGRESS_AFTER_S=0 " + std::string(ODONATA_FIT_EXE) +
                          " --train " + Example("train.csv") +
                          " --output y --input u --epochs 3 --no-select";
  const std::string cmd = "script -qec '" + fit + "' /dev/null 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  ASSERT_EQ(pclose(p), 0) << out;
  EXPECT_NE(out.find("epoch 3/3"), std::string::npos) << out;
  EXPECT_NE(out.find("100%"), std::string::npos);
}

void ExpectError(const std::string& args, const std::string& fragment) {
  const ProcessResult r = Exec(args);
  EXPECT_NE(r.status, 0) << args;
  EXPECT_LT(r.status, 128) << "crashed: " << r.out;
  EXPECT_NE(r.out.find(fragment), std::string::npos)
      << "expected '" << fragment << "' in: " << r.out;
}

// Issue 57: the data holds nothing to identify — said with what to do, exit 3, never a model.
TEST(FitCli, NothingToIdentifyIsAFindingWithItsOwnExitCode) {
  std::string flat = "k,u,y\n", still = "k,u,y\n";
  for (int k = 0; k < 400; ++k) {
    flat += std::to_string(k) + "," + std::to_string(k % 7) + ",0.5\n";             // y never moves
    still += std::to_string(k) + ",0," + std::to_string(std::sin(k * 0.1)) + "\n";  // nor u
  }
  const ProcessResult f = Exec("--train " + Write("flat.csv", flat) + " --output y --input u");
  EXPECT_EQ(f.status, 3) << f.out;
  EXPECT_NE(f.out.find("nothing to identify"), std::string::npos) << f.out;
  EXPECT_NE(f.out.find("the output 'y' never moves"), std::string::npos) << f.out;
  const ProcessResult s = Exec("--train " + Write("still.csv", still) + " --output y --input u");
  EXPECT_EQ(s.status, 3) << s.out;
  EXPECT_NE(s.out.find("the input 'u' never moves"), std::string::npos) << s.out;
  // 30 rows: settings would be chosen on 5 samples.
  std::string shortlog = "k,u,y\n";
  for (int k = 0; k < 30; ++k)
    shortlog +=
        std::to_string(k) + "," + std::to_string(k % 3) + "," + std::to_string(k % 5) + "\n";
  const ProcessResult r = Exec("--train " + Write("short.csv", shortlog) + " --output y --input u");
  EXPECT_EQ(r.status, 3) << r.out;
  EXPECT_NE(r.out.find("settings would be chosen on"), std::string::npos) << r.out;
  // A model that comes out a constant (one singleton rule) is no success either: flagged, exit 3.
  const ProcessResult c = Exec("--train " + std::string(ODONATA_EXAMPLES_DIR) +
                               "/narendra/train.csv --output y --input u --no-select --consequent "
                               "singleton --max-rules 1 --epochs 1");
  EXPECT_EQ(c.status, 3) << c.out;
  EXPECT_NE(c.out.find("the model is a constant"), std::string::npos) << c.out;
  // A window that keeps nothing.
  const ProcessResult w = Exec("--train " + Write("win.csv", flat) +
                               " --output y --input u --rate 100 --from 100 --to 101");
  EXPECT_EQ(w.status, 3) << w.out;
}

// Issue 61 finding 4: on a full disk (here: no file may grow) a configuration or ranges file is
// not left empty with exit 0: the run fails naming the file, and no file is left.
TEST(FitCli, AFileThatCannotBeWrittenIsAnErrorAndNoEmptyFileIsLeft) {
  for (const char* option : {"--save-config", "--save-ranges"}) {
    SCOPED_TRACE(option);
    const std::string out = Dir() + "/full_disk_" + std::string(option + 7) + ".json";
    std::remove(out.c_str());
    const ProcessResult r =
        Exec("sh -c 'trap \"\" XFSZ; ulimit -f 0; exec " + std::string(ODONATA_FIT_EXE) +
                 " --train " + std::string(ODONATA_EXAMPLES_DIR) +
                 "/narendra/train.csv --output y --input u "
                 "--no-select --epochs 1 " +
                 option + " " + out + "' 2>&1",
             true, true);
    EXPECT_EQ(r.status, 1) << r.out;
    EXPECT_NE(r.out.find(out), std::string::npos) << r.out;
    std::ifstream left(out);
    EXPECT_FALSE(left.good()) << "an empty or partial file was left";
  }
}

TEST(FitCli, SmallMistakesGetTheirFix) {
  std::string csv = "k,u,m2,time_ms\n";
  for (int k = 0; k < 300; ++k)
    csv += std::to_string(k) + "," + std::to_string(std::sin(k * 0.3)) + "," +
           std::to_string(std::sin(k * 0.3 - 0.2)) + "," + std::to_string(10 * k) + "\n";
  const std::string file = Write("small.csv", csv);
  // A column that differs only in case.
  ExpectError("--train " + file + " --output M2 --input u", "did you mean 'm2'?");
  // The output named as an input too.
  ExpectError("--train " + file + " --output m2 --input m2", "named as the output and as an input");
  // A time column in milliseconds, by its name: 100 Hz, and time constants in seconds.
  const ProcessResult ms = Exec(
      "--train " + file + " --output m2 --input u --time time_ms --no-select --epochs 1 --json",
      false);
  ASSERT_EQ(ms.status, 0) << ms.out;
  const nlohmann::json j = nlohmann::json::parse(ms.out);
  EXPECT_NEAR(j["data"][file]["rate_hz"].get<double>(), 100.0, 1e-6) << ms.out;
  EXPECT_TRUE(j["local_models"][0].contains("time_constants_s")) << j["local_models"][0].dump();
  // Each rule's parameter uncertainty beside it, in the same time unit (issue 60 point 2).
  const nlohmann::json& u = j["local_models"][0]["uncertainty"];
  EXPECT_TRUE(u.contains("time_constants_se_s")) << u.dump();
  EXPECT_TRUE(u.contains("dc_gain_se") && u["dc_gain_se"].contains("u")) << u.dump();
  EXPECT_GT(u["effective_rows"].get<double>(), 0.0) << u.dump();
  // A mistyped option is answered with the one meant.
  const ProcessResult typo = Exec("--train " + file + " --output m2 --inptu u");
  EXPECT_EQ(typo.status, 2);
  EXPECT_NE(typo.out.find("did you mean --input?"), std::string::npos) << typo.out;
}

TEST(FitCli, BadInputGivesAClearErrorNamingFileLineAndColumn) {
  const std::string ok = "k,u,y\n0,1,2\n1,2,3\n2,3,4\n3,4,5\n4,5,6\n";
  ExpectError("--train " + Dir() + "/missing.csv --output y --input u", "missing.csv");
  const std::string good = Write("good.csv", ok);
  ExpectError("--train " + good + " --output nope --input u", "no column named 'nope'");
  ExpectError("--train " + good + " --output y --input nope", "no column named 'nope'");
  ExpectError("--train " + Write("text.csv", "k,u,y\n0,1,2\n1,abc,3\n") + " --output y --input u",
              "text.csv:3: column 2 ('u'): 'abc' is not a number");
  // A NaN is a missing sample (docs/identifier.md §7.1): here it leaves too little to learn from.
  ExpectError("--train " + Write("nan.csv", "k,u,y\n0,1,2\n1,2,nan\n") + " --output y --input u",
              "nan.csv: 2 data rows, but no stretch of 3 samples");
  ExpectError("--train " + Write("inf.csv", "k,u,y\n0,inf,2\n") + " --output y --input u",
              "inf.csv:2: column 2 ('u'): 'inf' is not finite");
  ExpectError("--train " + Write("ragged.csv", "k,u,y\n0,1\n") + " --output y --input u",
              "ragged.csv:2: expected 3 cells, found 2");
  ExpectError("--train " + Write("empty.csv", "") + " --output y --input u",
              "empty.csv: no header");
  ExpectError(
      "--train " + Write("short.csv", "k,u,y\n0,1,2\n1,2,3\n") + " --output y --input u --ny 3",
      "short.csv: 2 data rows");
  ExpectError("--load-model " + Write("model.json", "{ broken") + " --validate " + good,
              "model.json: not valid JSON");
  ExpectError("--load-model " + Write("foreign.json", "{\"a\":1}") + " --validate " + good,
              "not an odonata model");
  ExpectError("--train " + good + " --output y --input u --consequent cubic", "cubic");
  ExpectError("--train " + good + " --output y --input u --entropy-threshold 0.9",
              "entropy threshold");
  ExpectError("--train " + good + " --output y --input u --forgetting 1.5", "forgetting");
  ExpectError("--train " + good + " --output y --input u --max-rules 2000000000", "max_rules");
  ExpectError("--output y --input u", "--train is required");
}

}  // namespace

namespace {

// A two-output vehicle: y1 answers u nonlinearly, y2 follows y1 (a coupled axis).
struct TwoOutputs {
  std::vector<double> u, y1, y2;
};
TwoOutputs Simulate(int n, unsigned seed) {
  TwoOutputs d;
  double y1 = 0, y2 = 0;
  unsigned s = seed;
  double level = 0;
  for (int k = 0; k < n; ++k) {
    if (k % 17 == 0) {
      s = s * 1103515245u + 12345u;
      level = -1.0 + 2.0 * ((s >> 8) % 10000) / 9999.0;
    }
    d.u.push_back(level);
    d.y1.push_back(y1);
    d.y2.push_back(y2);
    const double n1 = 0.6 * y1 + 0.5 * std::tanh(2.0 * level);
    y2 = 0.8 * y2 + 0.3 * y1;
    y1 = n1;
  }
  return d;
}

std::string TwoOutputsCsv(const std::string& name, int n, unsigned seed) {
  const TwoOutputs d = Simulate(n, seed);
  std::string text = "u,y1,y2\n";
  for (int k = 0; k < n; ++k)
    text += std::to_string(d.u[k]) + "," + std::to_string(d.y1[k]) + "," + std::to_string(d.y2[k]) +
            "\n";
  return Write(name, text);
}

}  // namespace

TEST(FitCli, SeveralOutputsInOneRunEachWithItsModelAndScores) {
  // The settings are what odonata-fit's selection chooses on the training file's own hold-out
  // (the validation file played no part), fixed here to keep the test fast.
  const ProcessResult r = Exec("--train " + TwoOutputsCsv("two_train.csv", 1500, 3) +
                                   " --validate " + TwoOutputsCsv("two_val.csv", 800, 9) +
                                   " --output y1 --output y2 --input u --consequent linear "
                                   "--entropy-threshold 0.1705336974719476 --kappa 0.5 "
                                   "--epochs 46 --json",
                               false);
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["outputs"], (nlohmann::json{"y1", "y2"}));
  ASSERT_TRUE(j.contains("per_output"));
  for (const char* name : {"y1", "y2"}) {
    const auto& b = j["per_output"][name];
    EXPECT_GT(b["rules"].get<int>(), 0) << name;
    const double fuzzy = b["validate"]["free_run"]["fit"].get<double>();
    EXPECT_GT(fuzzy, 90.0) << name;  // 99.9 % when written (ARX 81-83 %)
    EXPECT_GT(fuzzy, b["baselines"]["arx"]["validate"]["free_run"]["fit"].get<double>()) << name;
  }
  // The top level keeps the first output's figures, as a one-output report has them.
  EXPECT_EQ(j["validate"], j["per_output"]["y1"]["validate"]);
  // The readable report has a table for each.
  const ProcessResult text = Exec("--train " + Dir() +
                                  "/two_train.csv --output y1 --output y2 "
                                  "--input u --no-select");
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_NE(text.out.find("y1(k+1):"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("y2(k+1):"), std::string::npos) << text.out;
}

TEST(FitCli, AnIrregularTimeColumnIsResampledAndALongGapSplitsTheData) {
  // 100 Hz with ±2 ms jitter, and one second of the log missing in the middle.
  const TwoOutputs d = Simulate(2000, 5);
  std::string text = "t,u,y1\n";
  for (int k = 0; k < 2000; ++k) {
    if (k >= 900 && k < 1000) continue;
    const double t = 0.01 * k + 0.002 * std::sin(1.7 * k);
    text += std::to_string(t) + "," + std::to_string(d.u[k]) + "," + std::to_string(d.y1[k]) + "\n";
  }
  const std::string csv = Write("timed.csv", text);
  const ProcessResult r = Exec(
      "--train " + csv + " --time t --rate 100 --output y1 --input u --no-select --json", false);
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  const auto& data = j["data"][csv];
  EXPECT_EQ(data["rate_hz"].get<double>(), 100.0);
  EXPECT_EQ(data["segments"].get<int>(), 2) << data;
  EXPECT_GE(data["missing"].get<int>(), 95) << data;
  EXPECT_LE(data["missing"].get<int>(), 101) << data;
  EXPECT_GT(j["train"]["one_step"]["fit"].get<double>(), 90.0);
  EXPECT_FALSE(j["warnings"].empty());
  // Without --rate the file's median rate is taken.
  const ProcessResult median =
      Exec("--train " + csv + " --time t --output y1 --input u --no-select --json", false);
  ASSERT_EQ(median.status, 0) << median.out;
  EXPECT_NEAR(nlohmann::json::parse(median.out)["data"][csv]["rate_hz"].get<double>(), 100.0, 5.0);
  // Time that goes back is an error naming the row.
  ExpectError("--train " + Write("back.csv", "t,u,y1\n0,1,2\n0.02,1,2\n0.01,1,2\n") +
                  " --time t --output y1 --input u",
              "back.csv: data row 3: time 't' does not increase");
}

TEST(FitCli, ShortRunsOfMissingCellsAreBridgedAndLongOnesCut) {
  const TwoOutputs d = Simulate(1200, 7);
  std::string text = "u,y1\n";
  for (int k = 0; k < 1200; ++k) {
    const bool short_gap = k == 300 || k == 301;  // bridged
    const bool long_gap = k >= 600 && k < 620;    // cut
    text += (short_gap ? std::string("") : std::to_string(d.u[k])) + "," +
            (long_gap ? std::string("nan") : std::to_string(d.y1[k])) + "\n";
  }
  const std::string csv = Write("holes.csv", text);
  const ProcessResult r =
      Exec("--train " + csv + " --output y1 --input u --no-select --json", false);
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  const auto& data = j["data"][csv];
  EXPECT_EQ(data["bridged"].get<int>(), 2) << data;
  EXPECT_EQ(data["missing"].get<int>(), 20) << data;
  EXPECT_EQ(data["segments"].get<int>(), 2) << data;
  EXPECT_EQ(data["samples"].get<int>(), 1180) << data;
  // --max-gap 0 bridges nothing: the short gap cuts too.
  const ProcessResult strict =
      Exec("--train " + csv + " --output y1 --input u --no-select --max-gap 0 --json", false);
  ASSERT_EQ(strict.status, 0) << strict.out;
  EXPECT_EQ(nlohmann::json::parse(strict.out)["data"][csv]["segments"].get<int>(), 3);
}

namespace {

std::vector<std::vector<double>> ReadCsvNumbers(const std::string& path, std::string* header) {
  std::ifstream in(path);
  std::getline(in, *header);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::size_t at = 0;
    while (at <= line.size()) {
      const std::size_t comma = std::min(line.find(',', at), line.size());
      row.push_back(std::stod(line.substr(at, comma - at)));
      at = comma + 1;
    }
    rows.push_back(row);
  }
  return rows;
}

// Issue 49 point 4: --plot draws the readable terms, which rule fires when along the validation
// run, and the gain schedule of a dynamic model or the output surface of a static map, from data
// odonata-fit writes beside them (the firing is the model's own: each row's shares sum to 1).
TEST(FitCli, PlotDrawsTermsActivationAndGainScheduleOrSurface) {
  const std::string dynamic_dir = Dir() + "/plot-dynamic";
  const ProcessResult d =
      Exec("--train " + Example("train.csv") + " --validate " + Example("validate.csv") +
               " --output y --input u --consequent linear --no-select --epochs 2 --json --plot " +
               dynamic_dir,
           false);
  ASSERT_EQ(d.status, 0) << d.out;
  const auto j = nlohmann::json::parse(d.out);
  ASSERT_TRUE(j.contains("plots")) << j["warnings"];
  ASSERT_GT(j["rules"].get<int>(), 1);
  for (const char* f :
       {"membership.png", "activation.png", "gain_schedule.png", "gain_surface.png"})
    EXPECT_TRUE(std::ifstream(dynamic_dir + "/" + f).good()) << f;
  // The gain surface's header names its two signals (one lag of each) and the gain from u.
  std::string surface_header;
  ReadCsvNumbers(dynamic_dir + "/gain_surface.csv", &surface_header);
  EXPECT_NE(surface_header.find("gain from u"), std::string::npos) << surface_header;
  std::string header;
  const auto rows = ReadCsvNumbers(dynamic_dir + "/activation.csv", &header);
  ASSERT_GT(rows.size(), 100u);
  EXPECT_EQ(header.rfind("sample,t_s,measured,one_step,free_run,rule_1", 0), 0u) << header;
  for (const auto& r : rows) {
    double firing = 0;
    for (std::size_t c = 5; c < r.size(); ++c) firing += r[c];
    ASSERT_NEAR(firing, 1.0, 1e-9);
  }

  const std::string static_dir = Dir() + "/plot-static";
  const ProcessResult s = Exec("--train " + Example("train.csv") +
                                   " --output y --input u --ny 0 --delay 0 --no-select --json "
                                   "--plot " +
                                   static_dir,
                               false);
  ASSERT_EQ(s.status, 0) << s.out;
  EXPECT_TRUE(std::ifstream(static_dir + "/surface.png").good());
  EXPECT_TRUE(std::ifstream(static_dir + "/surface.csv").good());
}

}  // namespace
