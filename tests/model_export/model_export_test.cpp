// An exported model gives odonata's outputs in every client: the header-only inference, and
// fuzzylite reading the .fis and the .fll, on 1000 validation regressors, to within 1e-9.
// (Octave's fuzzy-logic-toolkit reads the same .fis in octave_fis_test.sh.)

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <sstream>

#include <fl/Headers.h>

#include "model_export/fis_writer.hpp"
#include "model_export/fll_writer.hpp"
#include "model_export/raw_tsk_model.hpp"
#include "odonata/tsk_model.hpp"
#include "sysid/model/free_run.hpp"
#include "trained_narendra_model.hpp"

namespace odonata::model_export {
namespace {

sysid::NarxModel Trained(fuzzy::ConsequentKind kind, bool uneven_output_widths) {
  return testing::TrainedNarendraModel(kind, uneven_output_widths);
}

// The 1000 validation regressors, raw units.
std::vector<Eigen::VectorXd> Regressors(const sysid::NarxModel& m) {
  const sysid::Series v = sysid::testing::NarendraValidate(1001);
  const auto data = sysid::BuildRegression(m.spec(), v);
  std::vector<Eigen::VectorXd> xs;
  for (Eigen::Index t = 0; t < data.x.rows() && xs.size() < 1000; ++t)
    xs.push_back(data.x.row(t).transpose());
  return xs;
}

double FuzzyliteOutput(fl::Engine& e, const Eigen::VectorXd& x) {
  for (int i = 0; i < x.size(); ++i)
    e.getInputVariable(static_cast<std::size_t>(i))->setValue(x(i));
  e.process();
  return e.getOutputVariable(0)->getValue();
}

struct Case {
  fuzzy::ConsequentKind kind;
  bool uneven_widths;
};

class ExportAgrees : public ::testing::TestWithParam<Case> {};

TEST_P(ExportAgrees, InEveryClientOnAThousandSamples) {
  const auto m = Trained(GetParam().kind, GetParam().uneven_widths);
  ASSERT_GT(m.total_rules(), 3);
  const inference::TskModel tsk = ToRawTsk(m, 0, "narendra");
  ASSERT_EQ(tsk.rules.size(), static_cast<std::size_t>(m.total_rules()));
  EXPECT_EQ(tsk.linear, GetParam().kind == fuzzy::ConsequentKind::kLinear);
  const std::string fis = ToFis(tsk), fll = ToFll(tsk);

  std::istringstream fis_in(fis);
  const inference::TskModel reread = inference::TskModel::FromFis(fis_in);
  // fuzzylite's defaults are for display, not for exact arithmetic (docs/model_export.md §3): its
  // tolerance (1e-6) treats smaller firing strengths as zero, and its FisImporter passes each
  // rule weight through a text rule printed with fuzzylite::decimals() (3) digits.
  fl::fuzzylite::setMachEps(1e-300);
  fl::fuzzylite::setDecimals(17);
  std::unique_ptr<fl::Engine> from_fis(fl::FisImporter().fromString(fis));
  std::unique_ptr<fl::Engine> from_fll(fl::FllImporter().fromString(fll));
  std::string why;
  ASSERT_TRUE(from_fis->isReady(&why)) << why;
  ASSERT_TRUE(from_fll->isReady(&why)) << why;
  ASSERT_EQ(from_fis->numberOfInputVariables(), tsk.inputs());

  double worst_header = 0, worst_fis = 0, worst_fll = 0, worst_reread = 0;
  const auto xs = Regressors(m);
  ASSERT_EQ(xs.size(), 1000u);
  for (const auto& x : xs) {
    const double want = m.Predict(x)(0);
    ASSERT_TRUE(std::isfinite(want));
    worst_header = std::max(worst_header, std::abs(tsk.Evaluate(x.data(), x.size()) - want));
    worst_reread = std::max(worst_reread, std::abs(reread.Evaluate(x.data(), x.size()) - want));
    worst_fis = std::max(worst_fis, std::abs(FuzzyliteOutput(*from_fis, x) - want));
    worst_fll = std::max(worst_fll, std::abs(FuzzyliteOutput(*from_fll, x) - want));
  }
  fl::fuzzylite::setMachEps(1e-6);
  fl::fuzzylite::setDecimals(3);
  EXPECT_LE(worst_header, 1e-9);
  EXPECT_LE(worst_reread, 1e-9);
  EXPECT_LE(worst_fis, 1e-9);
  EXPECT_LE(worst_fll, 1e-9);
  RecordProperty("max_abs_diff_fuzzylite_fis", std::to_string(worst_fis));
}

INSTANTIATE_TEST_SUITE_P(Kinds, ExportAgrees,
                         ::testing::Values(Case{fuzzy::ConsequentKind::kLinear, false},
                                           Case{fuzzy::ConsequentKind::kLinear, true},
                                           Case{fuzzy::ConsequentKind::kSingleton, true}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return std::string(fuzzy::ToString(info.param.kind)) +
                                  (info.param.uneven_widths ? "_rule_weights" : "_equal_weights");
                         });

TEST(ClientName, KeepsLagsReadable) {
  EXPECT_EQ(ClientName("vz(k-1)"), "vz_km1");
  EXPECT_EQ(ClientName("vz(k+1)"), "vz_kp1");
  EXPECT_EQ(ClientName("u(k)"), "u_k");
  EXPECT_EQ(ClientName("u_roll_applied_rad(k-12)"), "u_roll_applied_rad_km12");
  EXPECT_EQ(ClientName("2x"), "v_2x");
}

TEST(ToRawTsk, RefusesAModelWithoutRules) {
  fuzzy::FuzzyModelConfig cfg;
  const sysid::NarxModel empty(sysid::testing::NarendraSpec(), cfg);
  EXPECT_THROW(ToRawTsk(empty, 0), std::invalid_argument);
  EXPECT_THROW(ToRawTsk(empty, 1), std::invalid_argument);
}

TEST(TskModelFromFis, NamesTheLineOfABadFile) {
  const auto m = Trained(fuzzy::ConsequentKind::kLinear, false);
  std::string fis = ToFis(ToRawTsk(m, 0));
  const auto bad = [](std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  const auto message = [](const std::string& text) -> std::string {
    std::istringstream in(text);
    try {
      inference::TskModel::FromFis(in);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message(bad(fis, "Type='sugeno'", "Type='mamdani'")).find("sugeno"), std::string::npos);
  EXPECT_NE(message(bad(fis, "'gaussmf',[", "'gaussmf',[x")).find("not a finite number"),
            std::string::npos);
  EXPECT_NE(message(bad(fis, "NumRules=", "NumRules=1")).find("NumRules"), std::string::npos);
  EXPECT_NE(message(bad(fis, "[Rules]\n1 1, 1", "[Rules]\n1 99, 1")).find("line"),
            std::string::npos);
  EXPECT_NE(message(bad(fis, "[Output1]", "[Output2]")).find("Output1"), std::string::npos);
  const double x[] = {0.1};
  std::istringstream ok(fis);
  EXPECT_TRUE(std::isnan(inference::TskModel::FromFis(ok).Evaluate(x, 1)));  // wrong input count
}

}  // namespace
}  // namespace odonata::model_export
