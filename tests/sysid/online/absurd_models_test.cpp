// Issue 51 point 1's probe of absurd model files, over every number a model file holds: a trained
// model's JSON with one number replaced by an absurd value (±1e300, 0, 1e-300, −1, 1e15). Each
// file is refused by the reader with a message, or an identifier started from it predicts only
// finite values (one step and free run) while it learns on, and the model it then holds is either
// refused by Save or written and read back — never a file odonata-fit cannot read.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "online_fixtures.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/online/online_identifier.hpp"

namespace odonata::sysid {
namespace {

using testing::Row;

// Every number's pointer, taking the first element of each array (its siblings are alike).
void NumberPaths(const nlohmann::json& j, const nlohmann::json::json_pointer& at,
                 std::vector<nlohmann::json::json_pointer>* out) {
  if (j.is_number()) {
    out->push_back(at);
  } else if (j.is_object()) {
    for (const auto& [key, value] : j.items()) NumberPaths(value, at / key, out);
  } else if (j.is_array() && !j.empty()) {
    NumberPaths(j[0], at / 0, out);
  }
}

TEST(AbsurdModels, EveryAbsurdNumberIsRefusedOrPredictsFinitely) {
  const Series train = testing::NarendraTrain(1500);
  const Series run = testing::NarendraValidate(300);
  OnlineIdentifier learner(testing::Empty(fuzzy::ConsequentKind::kLinear, train));
  for (Eigen::Index k = 0; k < train.outputs.rows(); ++k) learner.Push(Row(train, k));
  ASSERT_GT(learner.model().total_rules(), 1);
  const nlohmann::json trained = learner.model().ToJson();
  std::vector<nlohmann::json::json_pointer> paths;
  NumberPaths(trained, nlohmann::json::json_pointer(), &paths);
  ASSERT_GE(paths.size(), 25u);

  const std::string saved = ::testing::TempDir() + "absurd_model.json";
  int refused = 0, started = 0;
  for (const auto& path : paths) {
    for (const double value : {1e300, -1e300, 0.0, 1e-300, -1.0, 1e15}) {
      nlohmann::json j = trained;
      j[path] = value;
      const std::string what = path.to_string() + " = " + std::to_string(value);
      std::optional<NarxModel> model;
      try {
        model = NarxModel::FromJson(j);
      } catch (const std::exception& e) {
        EXPECT_GT(std::string(e.what()).size(), 10u) << what;
        ++refused;
        continue;
      }
      ++started;
      OnlineIdentifier id(*model);
      for (Eigen::Index k = 0; k < run.outputs.rows(); ++k) {
        const auto report = id.Push(Row(run, k));
        if (!report) continue;
        ASSERT_TRUE(report->predicted.allFinite()) << what << " at sample " << k;
        ASSERT_TRUE(report->free_run.allFinite()) << what << " at sample " << k;
      }
      bool written = false;
      try {
        id.model().Save(saved);
        written = true;
      } catch (const std::exception&) {
        // refused: nothing written that the reader would refuse
      }
      if (written) {
        EXPECT_NO_THROW(NarxModel::Load(saved)) << what;
      }
    }
  }
  std::remove(saved.c_str());
  // Both happen: the probe is not vacuous either way.
  EXPECT_GT(refused, 0);
  EXPECT_GT(started, 0);
  std::printf("%zu numbers x 6 absurd values: %d refused with a message, %d started and finite\n",
              paths.size(), refused, started);
}

}  // namespace
}  // namespace odonata::sysid
