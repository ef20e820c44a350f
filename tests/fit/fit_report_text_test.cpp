// odonata-fit's text report (issue 57): one meaning per number — a diverging prediction prints as
// "diverges", never as a 28-digit FIT; the verdict comes first; a model's rule count is one number
// (the chosen candidate's line names the final model's when training on every row changed it).
#include "fit/fit_report_text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace odonata::fit {
namespace {

nlohmann::json Scores(double fit, bool diverged) {
  nlohmann::json j = {{"fit", fit}, {"vaf", 50.0}, {"rmse", 0.1}, {"ndei", 0.5}, {"samples", 100}};
  if (diverged) j["diverged"] = true;
  return j;
}

nlohmann::json Report() {
  nlohmann::json r;
  r["target"] = "q(k+1)";
  r["regressors"] = {"q(k)", "u(k)"};
  r["rules"] = 10;
  r["consequent"] = "linear";
  r["entropy_threshold"] = 0.4;
  r["kappa"] = 1.0;
  r["epochs"] = 5;
  r["max_rules"] = 100;
  r["verdict"] = {{"text", "validation, free run: FIT diverges (ARX 12.00 %, persistence 0.00 %)"}};
  r["train"] = {{"one_step", Scores(90.0, false)}, {"free_run", Scores(-6.3e27, true)}};
  r["baselines"]["arx"]["train"] = {{"one_step", Scores(80.0, false)},
                                    {"free_run", Scores(12.0, false)}};
  nlohmann::json candidate = {{"consequent", "linear"},
                              {"entropy_threshold", 0.4},
                              {"kappa", 1.0},
                              {"epochs", 5},
                              {"rules", 11},
                              {"holdout_one_step_ndei", 0.1},
                              {"holdout_free_run_ndei", 0.2},
                              {"simulation", nlohmann::json::array()}};
  r["selection"] = {{"holdout_samples", 200},
                    {"criterion", "free_run"},
                    {"relative_tolerance", 0.05},
                    {"absolute_tolerance", 0.005},
                    {"candidates", {candidate}},
                    {"chosen_index", 0},
                    {"best_index", 0}};
  return r;
}

TEST(FitReportText, ADivergingPredictionPrintsAsDivergesAndTheVerdictComesFirst) {
  const std::string text = FormatReport(Report(), RulesShown::kNone);
  EXPECT_EQ(text.find("6311"), std::string::npos) << text;
  EXPECT_EQ(text.find("e+27"), std::string::npos) << text;
  EXPECT_NE(text.find("free_run   fuzzy       diverges"), std::string::npos) << text;
  const std::size_t verdict = text.find("verdict: validation, free run");
  ASSERT_NE(verdict, std::string::npos) << text;
  EXPECT_LT(verdict, text.find("model selection")) << text;
}

TEST(FitReportText, TheChosenCandidateNamesTheFinalModelsRuleCount) {
  const std::string text = FormatReport(Report(), RulesShown::kNone);
  EXPECT_NE(text.find("10 rules (linear consequents)"), std::string::npos) << text;
  EXPECT_NE(text.find("(the model, trained on every row: 10 rules)"), std::string::npos) << text;
  nlohmann::json same = Report();
  same["selection"]["candidates"][0]["rules"] = 10;
  EXPECT_EQ(FormatReport(same, RulesShown::kNone).find("trained on every row"), std::string::npos);
}

}  // namespace
}  // namespace odonata::fit
