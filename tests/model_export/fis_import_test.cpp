// A .fis taken back in (issue 21 point 4): the rules odonata-export wrote, unfolded into an
// identifier's regressor and ranges — other ranges than the model was trained with — predict
// what the exported model predicts, and a file that does not fit is refused with why.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>
#include "model_export/fis_import.hpp"
#include "model_export/fis_writer.hpp"
#include "model_export/raw_tsk_model.hpp"

#include "sysid/model/rule_listing.hpp"
#include "sysid/model/signal_ranges.hpp"
#include "sysid/online/online_identifier.hpp"
#include "trained_narendra_model.hpp"

namespace odonata::model_export {
namespace {

sysid::NarxModel Trained(fuzzy::ConsequentKind kind) { return testing::TrainedNarendraModel(kind); }

// An identifier's empty model: the same regressor, its own declared ranges.
sysid::NarxModel Empty(fuzzy::ConsequentKind kind) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = kind;
  sysid::NarxModel m(sysid::testing::NarendraSpec(), cfg);
  m.SetScaling(sysid::ScalingFromRanges(sysid::testing::NarendraSpec(),
                                        {{"y", {-12.0, 9.0}}, {"u", {-2.5, 2.0}}}));
  return m;
}

inference::TskModel Parsed(const std::string& fis) {
  std::istringstream in(fis);
  return inference::TskModel::FromFis(in);
}

TEST(FisImport, TheIdentifierStartsFromTheRulesAndPredictsWhatTheyPredict) {
  for (const auto kind : {fuzzy::ConsequentKind::kLinear, fuzzy::ConsequentKind::kSingleton}) {
    const sysid::NarxModel trained = Trained(kind);
    const std::string fis = ToFis(ToRawTsk(trained, 0, "narendra"));
    const sysid::NarxModel started = ModelFromTsk(Parsed(fis), Empty(kind), "narendra.fis");
    EXPECT_EQ(started.total_rules(), trained.total_rules());
    const auto data = sysid::BuildRegression(trained.spec(), sysid::testing::NarendraValidate(500));
    double worst = 0;
    for (Eigen::Index t = 0; t < data.x.rows(); ++t) {
      const Eigen::VectorXd x = data.x.row(t).transpose();
      worst = std::max(worst, std::abs(started.Predict(x)(0) - trained.Predict(x)(0)));
    }
    EXPECT_LT(worst, 1e-9) << fuzzy::ToString(kind);
  }
  // Constant rule outputs start a linear model with zero slopes.
  const sysid::NarxModel singleton = Trained(fuzzy::ConsequentKind::kSingleton);
  const std::string constant = ToFis(ToRawTsk(singleton, 0, "narendra"));
  const sysid::NarxModel as_linear =
      ModelFromTsk(Parsed(constant), Empty(fuzzy::ConsequentKind::kLinear), "c.fis");
  Eigen::VectorXd x(2);
  x << 0.3, -0.4;
  EXPECT_NEAR(as_linear.Predict(x)(0), singleton.Predict(x)(0), 1e-9);
}

// MATLAB's "don't care": a 0 for an input in a rule line leaves that input out of the rule's
// premise (issue 47 point 4: an expert's rule base was refused). evalfis gives that input a
// membership of 1; so does the reader, and the identifier started from the file predicts the same.
TEST(FisImport, ARuleThatLeavesAnInputOutIsRead) {
  const sysid::NarxModel trained = Trained(fuzzy::ConsequentKind::kLinear);
  ASSERT_GE(trained.total_rules(), 2);
  std::string fis = ToFis(ToRawTsk(trained, 0, "narendra"));
  const auto at = fis.find("[Rules]\n1 1, 1");
  ASSERT_NE(at, std::string::npos) << fis;
  fis.replace(at, 14, "[Rules]\n1 0, 1");  // rule 1 no longer looks at u(k-1)
  const inference::TskModel tsk = Parsed(fis);
  EXPECT_TRUE(std::isinf(tsk.rules[0].sigma[1]));
  const sysid::NarxModel started =
      ModelFromTsk(tsk, Empty(fuzzy::ConsequentKind::kLinear), "dc.fis");
  EXPECT_EQ(started.total_rules(), trained.total_rules());
  EXPECT_DOUBLE_EQ(started.model(0).rule_base().sigma(0, 1), kDontCareWidth);
  const auto data = sysid::BuildRegression(trained.spec(), sysid::testing::NarendraValidate(500));
  double worst = 0, moved = 0;
  for (Eigen::Index t = 0; t < data.x.rows(); ++t) {
    const Eigen::VectorXd x = data.x.row(t).transpose();
    const double from_file = tsk.Evaluate(x.data(), 2);
    worst = std::max(worst, std::abs(started.Predict(x)(0) - from_file));
    moved = std::max(moved, std::abs(from_file - trained.Predict(x)(0)));
  }
  EXPECT_LT(worst, 1e-4) << "the identifier predicts what the file does";
  EXPECT_GT(moved, 1e-3) << "leaving the input out changed the model";
  // A negated term (MATLAB's NOT) is still refused, naming the line.
  std::string negated = ToFis(ToRawTsk(trained, 0, "narendra"));
  negated.replace(negated.find("[Rules]\n1 1, 1"), 14, "[Rules]\n1 -1, 1");
  std::istringstream in(negated);
  try {
    inference::TskModel::FromFis(in);
    FAIL() << "a negated term was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("line"), std::string::npos) << e.what();
  }
}

// An expert's words stay with the rules (issue 47 point 4): the membership functions' names are
// the rules' term names, read into the model, printed in its rules and kept in its file; the
// placeholder names odonata-export writes ("r1") are not names.
TEST(FisImport, TheExpertsTermNamesAreKeptAndPrinted) {
  const sysid::NarxModel trained = Trained(fuzzy::ConsequentKind::kLinear);
  ASSERT_GE(trained.total_rules(), 2);
  const std::string exported = ToFis(ToRawTsk(trained, 0, "narendra"));
  const sysid::NarxModel plain =
      ModelFromTsk(Parsed(exported), Empty(fuzzy::ConsequentKind::kLinear), "plain.fis");
  EXPECT_FALSE(plain.model(0).named()) << "odonata-export's r1, r2 … are placeholders";
  std::string fis = exported;
  // Input 1's first function and the first output function get an expert's names.
  fis.replace(fis.find("MF1='r1':'gaussmf'"), 18, "MF1='low':'gaussmf'");
  fis.replace(fis.find("MF1='r1':'linear'"), 17, "MF1='hover':'linear'");
  const sysid::NarxModel named =
      ModelFromTsk(Parsed(fis), Empty(fuzzy::ConsequentKind::kLinear), "named.fis");
  ASSERT_TRUE(named.model(0).named());
  EXPECT_EQ(named.model(0).names(0).terms.at(0), "low");
  EXPECT_EQ(named.model(0).names(0).terms.at(1), "");
  EXPECT_EQ(named.model(0).names(0).output, "hover");
  EXPECT_TRUE(named.model(0).names(1).empty());
  const auto rules = sysid::DescribeRules(named, 0);
  EXPECT_NE(rules.at(0).find(" is low (≈"), std::string::npos) << rules.at(0);
  EXPECT_NE(rules.at(0).find("[hover]"), std::string::npos) << rules.at(0);
  const sysid::NarxModel reread = sysid::NarxModel::FromJson(named.ToJson());
  EXPECT_EQ(reread.model(0).names(0), named.model(0).names(0));
  // Predictions do not depend on the names.
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(named.spec().size(), -0.3, 0.4);
  EXPECT_EQ(named.Predict(x), plain.Predict(x));
}

TEST(FisImport, AFileThatDoesNotFitIsRefusedWithWhy) {
  const sysid::NarxModel trained = Trained(fuzzy::ConsequentKind::kLinear);
  inference::TskModel tsk = ToRawTsk(trained, 0, "narendra");
  auto message = [](const auto& f) {
    try {
      f();
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  inference::TskModel renamed = tsk;
  renamed.input_names[1] = "throttle_k";
  const std::string names =
      message([&] { ModelFromTsk(renamed, Empty(fuzzy::ConsequentKind::kLinear), "mine.fis"); });
  EXPECT_NE(names.find("mine.fis"), std::string::npos) << names;
  EXPECT_NE(names.find("[y_k, throttle_k]"), std::string::npos) << names;
  EXPECT_NE(names.find("[y_k, u_k]"), std::string::npos) << names;
  const std::string kind =
      message([&] { ModelFromTsk(tsk, Empty(fuzzy::ConsequentKind::kSingleton), "mine.fis"); });
  EXPECT_NE(kind.find("singleton"), std::string::npos) << kind;
  // A malformed file: the line at fault, and the file's name.
  const std::string path = ::testing::TempDir() + "/bad.fis";
  std::string fis = ToFis(tsk);
  fis.replace(fis.find("gaussmf"), 7, "trimf");
  std::ofstream(path) << fis;
  const std::string bad = message([&] { LoadFis(path, Empty(fuzzy::ConsequentKind::kLinear)); });
  EXPECT_NE(bad.find(path), std::string::npos) << bad;
  EXPECT_NE(bad.find("line"), std::string::npos) << bad;
  std::remove(path.c_str());
}

// Issue 51 point 1 for .fis files: every number of an exported file replaced in turn by an
// absurd value (±1e308, 0, 1e-308). Each file is refused with a message, or an identifier started
// from it predicts only finite values (one step and free run) while it learns on.
TEST(FisImport, EveryAbsurdNumberIsRefusedOrPredictsFinitely) {
  const std::string fis = ToFis(ToRawTsk(Trained(fuzzy::ConsequentKind::kLinear), 0, "narendra"));
  const std::regex number(R"([-+]?[0-9]+\.?[0-9]*(e[-+]?[0-9]+)?)");
  std::vector<std::pair<std::size_t, std::size_t>> spans;  // the numbers in the MF and rule lines
  std::size_t line_start = 0;
  while (line_start < fis.size()) {
    const std::size_t end = std::min(fis.find('\n', line_start), fis.size());
    const std::string line = fis.substr(line_start, end - line_start);
    if (line.rfind("MF", 0) == 0 || line.rfind("Range", 0) == 0) {
      for (auto it = std::sregex_iterator(line.begin(), line.end(), number);
           it != std::sregex_iterator(); ++it) {
        const std::size_t at = static_cast<std::size_t>(it->position());
        if (at > 0 && (std::isalnum(static_cast<unsigned char>(line[at - 1])) != 0)) continue;
        spans.emplace_back(line_start + at, static_cast<std::size_t>(it->length()));
      }
    }
    line_start = end + 1;
  }
  ASSERT_GE(spans.size(), 10u);
  const auto run = sysid::testing::NarendraValidate(300);
  int refused = 0, started = 0;
  for (const auto& [at, length] : spans) {
    for (const char* value : {"1e308", "-1e308", "0", "1e-308"}) {
      std::string text = fis;
      text.replace(at, length, value);
      const std::string what =
          fis.substr(at, length) + " -> " + value + " at byte " + std::to_string(at);
      std::optional<sysid::NarxModel> model;
      try {
        model = ModelFromTsk(Parsed(text), Empty(fuzzy::ConsequentKind::kLinear), "probe.fis");
      } catch (const std::exception& e) {
        EXPECT_GT(std::string(e.what()).size(), 10u) << what;
        ++refused;
        continue;
      }
      ++started;
      sysid::OnlineIdentifier id(*model);
      for (Eigen::Index k = 0; k < run.outputs.rows(); ++k) {
        const auto report =
            id.Push({k, run.outputs.row(k).transpose(), run.inputs.row(k).transpose()});
        if (!report) continue;
        ASSERT_TRUE(report->predicted.allFinite()) << what << " at sample " << k;
        ASSERT_TRUE(report->free_run.allFinite()) << what << " at sample " << k;
      }
    }
  }
  EXPECT_GT(refused, 0);
  EXPECT_GT(started, 0);
  std::printf("%zu numbers x 4 absurd values: %d refused with a message, %d started and finite\n",
              spans.size(), refused, started);
}

}  // namespace
}  // namespace odonata::model_export
