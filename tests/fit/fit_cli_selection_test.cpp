// odonata-fit's contract where it runs whole model selections (progress, the saved
// configuration, the validation file never read, the online replay's report): about 30–50 s each
// under the sanitizers, so these run in the Release suite only (tests/fit/CMakeLists.txt).

#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fit_process.hpp"

namespace {

using namespace odonata::fit_process;

// Into a log (stderr not a terminal), a long fit says where it is, with the time left once its
// pace is known; with --json into a pipe it says nothing. The quiet time is 0 here, so any fit
// is "long".
TEST(FitCli, ProgressLinesInALogAndSilenceWithJson) {
  const std::string args = "--train " + ShortTrain() +
                           " --output y --input u --consequent linear --select-kappas 1 "
                           "--select-thresholds 0.3,0.45 --max-epochs 3";
  const ProcessResult text = Exec("env ODONATA_PROGRESS_AFTER_S=0 " + std::string(ODONATA_FIT_EXE) +
                                      " " + args + " 2>&1 >/dev/null",
                                  false, true);
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_NE(text.out.find("odonata-fit: selecting linear"), std::string::npos) << text.out;
  EXPECT_EQ(text.out.find("\r"), std::string::npos) << "no bar redrawn into a log";
  const ProcessResult json = Exec("env ODONATA_PROGRESS_AFTER_S=0 " + std::string(ODONATA_FIT_EXE) +
                                      " " + args + " --json 2>&1 >/dev/null",
                                  false, true);
  ASSERT_EQ(json.status, 0) << json.out;
  EXPECT_EQ(json.out.find("odonata-fit: selecting"), std::string::npos)
      << "progress with --json into a pipe: " << json.out;
}

// Choices carried across (issue 21 point 4): the configuration odonata-fit writes is one
// odonata-identifier accepts as it is, with the settings the selection chose.
TEST(FitCli, SavedConfigurationIsOneTheIdentifierTakesAsItIs) {
  const std::string cfg = Dir() + "/saved_identifier.json";
  const ProcessResult fit =
      Exec("--train " + ShortTrain() +
               " --output y --input u --consequent linear --select-kappas 0.5 "
               "--select-thresholds 0.3,0.45 --max-epochs 3 --json --save-config " +
               cfg,
           false);
  ASSERT_EQ(fit.status, 0) << fit.out;
  const auto report = nlohmann::json::parse(fit.out);
  std::ifstream in(cfg);
  const auto c = nlohmann::json::parse(in);
  EXPECT_EQ(c["outputs"], nlohmann::json::array({"y"}));
  EXPECT_EQ(c["inputs"], nlohmann::json::array({"u"}));
  EXPECT_EQ(c["kappa"].get<double>(), 0.5);
  EXPECT_EQ(c["entropy_threshold"].get<double>(), report["entropy_threshold"].get<double>());
  EXPECT_TRUE(c["ranges"].contains("y") && c["ranges"].contains("u")) << c.dump();
  EXPECT_EQ(c["refit_horizon"].get<int>(), 0) << "chosen in free run, and so are its refits";
  const ProcessResult check =
      Exec(std::string(ODONATA_IDENTIFIER_EXE) + " --config " + cfg + " --check-config 2>&1", false,
           true);
  ASSERT_EQ(check.status, 0) << check.out;
  EXPECT_NE(check.out.find("identifies y from u (ny 1, nu 1, delay 1), linear consequents"),
            std::string::npos)
      << check.out;
  // A broken one is refused, naming the key.
  std::ofstream(cfg) << R"({"outputs": ["y"], "inputs": ["u"], "kapa": 1})";
  const ProcessResult bad =
      Exec(std::string(ODONATA_IDENTIFIER_EXE) + " --config " + cfg + " --check-config 2>&1", false,
           true);
  EXPECT_NE(bad.status, 0) << bad.out;
  EXPECT_NE(bad.out.find("kapa"), std::string::npos) << bad.out;
}

TEST(FitCli, SelectionNeverReadsTheValidationFile) {
  // The same training file with two different validation files: the same choice, same model.
  const std::string base = "--train " + ShortTrain() +
                           " --output y --input u --consequent linear --select-kappas 0.5,1 "
                           "--select-thresholds 0.3,0.45 --max-epochs 4 --json --validate ";
  const ProcessResult a = Exec(base + Example("validate.csv"), false);
  const ProcessResult b = Exec(base + Example("train.csv"), false);
  ASSERT_EQ(a.status, 0) << a.out;
  ASSERT_EQ(b.status, 0) << b.out;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  EXPECT_EQ(ja["selection"], jb["selection"]);
  EXPECT_EQ(ja["rule_text"], jb["rule_text"]);
  EXPECT_EQ(ja["train"], jb["train"]);
  // The validation's prediction intervals, calibrated on the selection's hold-out (never on the
  // validation file): each mode scored holds its level, coverage and mean width (issue 60).
  for (const char* mode : {"one_step", "free_run"}) {
    const nlohmann::json& i = ja["validate"][mode]["interval"];
    EXPECT_EQ(i["level"].get<double>(), 0.9) << mode;
    EXPECT_GE(i["coverage"].get<double>(), 0.0) << mode;
    EXPECT_LE(i["coverage"].get<double>(), 1.0) << mode;
    EXPECT_GT(i["calibration_rows"].get<long>(), 0) << mode;
    EXPECT_EQ(i["calibration_rows"], jb["validate"][mode]["interval"]["calibration_rows"]);
  }
}

// The predictions file carries each mode's interval, and its coverage is the report's.
TEST(FitCli, PredictionsFileHoldsTheIntervalsTheReportScores) {
  const std::string out = Dir() + "/pred_intervals.csv";
  const ProcessResult r = Exec("--train " + ShortTrain() +
                                   " --output y --input u --consequent linear --select-kappas 1 "
                                   "--select-thresholds 0.45 --max-epochs 3 --json --validate " +
                                   Example("validate.csv") + " --predictions " + out,
                               false);
  ASSERT_EQ(r.status, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  std::ifstream in(out);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header,
            "set,sample,measured,fuzzy_one_step,fuzzy_free_run,arx_one_step,arx_free_run,"
            "fuzzy_one_step_lower,fuzzy_one_step_upper,fuzzy_free_run_lower,fuzzy_free_run_upper");
  long validate = 0, covered = 0;
  while (std::getline(in, line)) {
    const std::vector<double> v = CsvNumbers(line, 9);
    if (v[0] != 1.0) continue;
    ++validate;
    if (v[7] <= v[2] && v[2] <= v[8]) ++covered;
  }
  ASSERT_GT(validate, 0);
  EXPECT_NEAR(static_cast<double>(covered) / static_cast<double>(validate),
              j["validate"]["one_step"]["interval"]["coverage"].get<double>(), 1e-12);
}

// Chosen K steps ahead, the report gives the one-step bound and which candidates it put out; the
// model kept is within it. In free run: none.
TEST(FitCli, KStepsAheadTheReportGivesTheOneStepBound) {
  const std::string args = "--train " + TrainHead(600) +
                           " --output y --input u --consequent linear --select-kappas 1 "
                           "--select-thresholds 0.3,0.45 --max-epochs 3";
  const std::string base = args + " --json";
  const std::string cfg = Dir() + "/k_step_identifier.json";
  const ProcessResult ahead = Exec(base + " --horizon 5 --save-config " + cfg, false);
  ASSERT_EQ(ahead.status, 0) << ahead.out;
  {
    // The identifier it configures refits choosing as this fit chose.
    std::ifstream in(cfg);
    EXPECT_EQ(nlohmann::json::parse(in)["refit_horizon"].get<int>(), 5);
    const ProcessResult check =
        Exec(std::string(ODONATA_IDENTIFIER_EXE) + " --config " + cfg + " --check-config 2>&1",
             false, true);
    ASSERT_EQ(check.status, 0) << check.out;
    EXPECT_NE(check.out.find("refits on, choosing 5 steps ahead"), std::string::npos) << check.out;
  }
  const auto sel = nlohmann::json::parse(ahead.out)["selection"];
  ASSERT_EQ(sel["criterion"], "k_step");
  ASSERT_TRUE(sel["one_step_bound"].is_number()) << sel.dump();
  const double bound = sel["one_step_bound"].get<double>();
  // ARX's one-step NDEI before its own simulation training (the JSON lists it after) plus the
  // margin: at least the absolute tolerance.
  EXPECT_GE(bound, sel["absolute_tolerance"].get<double>());
  const auto& cands = sel["candidates"];
  for (const auto& c : cands) {
    ASSERT_TRUE(c["one_step_lost"].is_boolean()) << c.dump();
    // The score is the K-step hold-out NDEI, which the report lists beside the other two.
    ASSERT_TRUE(c["holdout_ahead_ndei"].is_number()) << c.dump();
    if (!c["one_step_lost"].get<bool>()) {
      EXPECT_EQ(c["score"].get<double>(), c["holdout_ahead_ndei"].get<double>()) << c.dump();
    }
    if (c["linear"].get<bool>()) continue;
    EXPECT_EQ(c["one_step_lost"].get<bool>(), c["holdout_one_step_ndei"].get<double>() > bound)
        << c.dump();
  }
  const auto& chosen = cands[sel["chosen_index"].get<std::size_t>()];
  EXPECT_LE(chosen["holdout_one_step_ndei"].get<double>(), bound);
  const ProcessResult free_run = Exec(base, false);
  ASSERT_EQ(free_run.status, 0) << free_run.out;
  const auto free_sel = nlohmann::json::parse(free_run.out)["selection"];
  EXPECT_TRUE(free_sel["one_step_bound"].is_null());
  for (const auto& c : free_sel["candidates"]) EXPECT_TRUE(c["holdout_ahead_ndei"].is_null());
  // The text report's table has the K-step column, with the chosen candidate's score in it.
  const ProcessResult text = Exec(args + " --horizon 5", false);
  ASSERT_EQ(text.status, 0) << text.out;
  EXPECT_NE(text.out.find("free-run NDEI    5-step NDEI  ridge"), std::string::npos) << text.out;
  char cell[32];
  std::snprintf(cell, sizeof cell, "%13.4g", chosen["holdout_ahead_ndei"].get<double>());
  const auto star = text.out.find("\n    * ");
  ASSERT_NE(star, std::string::npos) << text.out;
  EXPECT_NE(text.out.substr(star, text.out.find('\n', star + 1) - star).find(cell),
            std::string::npos)
      << text.out;
}

// Replaying the online identifier (--refit-*) says what its refits did, in both reports.
TEST(FitCli, TheOnlineReplaySaysWhatItsRefitsDid) {
  const std::string args = "--train " + TrainHead(400) +
                           " --output y --input u --epochs 1 --no-least-squares --consequent "
                           "linear --refit-first 100 --refit-every 200 --refit-buffer 300";
  const ProcessResult text = Exec(args);
  ASSERT_EQ(text.status, 0) << text.out;
  // 100 lands at 200, where 200 begins; the freeze replaces that one with the closing refit.
  EXPECT_NE(text.out.find("the online identifier replayed: 399 samples learned, 2 refits landed "
                          "(0 failed, 0 kept the last refit's model, 0 steady-state models "
                          "refused by their checks, 0 landed the linear model, which won on the "
                          "samples since they began)"),
            std::string::npos)
      << text.out;
  const ProcessResult json = Exec(args + " --json", false);
  ASSERT_EQ(json.status, 0) << json.out;
  const auto refits = nlohmann::json::parse(json.out)["refits"];
  EXPECT_EQ(refits["landed"].get<int>(), 2);
  EXPECT_EQ(refits["incumbents_kept"].get<int>(), 0);
  EXPECT_EQ(refits["steady_state_refused"].get<int>(), 0);
  EXPECT_EQ(refits["linear_landed"].get<int>(), 0);
  EXPECT_EQ(refits["samples_learned"].get<int>(), 399);
}

}  // namespace
