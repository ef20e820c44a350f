// A .fis taken back in (issue 21 point 4): the rules odonata-export wrote, unfolded into an
// identifier's regressor and ranges — other ranges than the model was trained with — predict
// what the exported model predicts, and a file that does not fit is refused with why.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "model_export/fis_import.hpp"
#include "model_export/fis_writer.hpp"
#include "model_export/raw_tsk_model.hpp"
#include "sysid/signal_ranges.hpp"
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

}  // namespace
}  // namespace odonata::model_export
