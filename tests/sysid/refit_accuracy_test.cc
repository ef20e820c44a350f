// The scheduled refits' accuracy against the per-sample learner alone: three whole model
// selections on up to 1000 samples, a few seconds in Release and minutes under the sanitizers,
// so this executable is labelled slow (Release only). The refit machinery itself (worker thread,
// landings, replay) is tested under the sanitizers by online_identifier_test.cc.

#include <cstdio>

#include <gtest/gtest.h>

#include "narendra_series.hpp"
#include "online_fixtures.hpp"
#include "sysid/online_identifier.hpp"

namespace odonata::sysid {
namespace {

using testing::Empty;
using testing::Row;

TEST(OnlineIdentifier, RefitsLearnFarBetterThanThePerSampleLearnerAlone) {
  const Series train = testing::NarendraTrain(1500);
  const Series validate = testing::NarendraValidate(500);
  RefitSchedule refit;
  refit.first = 250;
  refit.every = 500;
  refit.buffer = 1000;  // the last 1000 samples only
  refit.at_freeze = false;
  OnlineIdentifier plain(Empty(fuzzy::ConsequentKind::kLinear, train));
  OnlineIdentifier refitted(Empty(fuzzy::ConsequentKind::kLinear, train), refit);
  for (Eigen::Index k = 0; k < train.samples(); ++k) {
    plain.Push(Row(train, k));
    refitted.Push(Row(train, k));
  }
  refitted.Freeze();  // the refit in flight (begun at 1000) closes; no closing refit of its own
  refitted.Settle();
  const double with = refitted.model().Ndei(validate, true);
  EXPECT_EQ(refitted.refits(), 3);  // begun at 250, 500 and 1000
  const double without = plain.model().Ndei(validate, true);
  std::printf("validation free-run NDEI %.4f with refits, %.4f without\n", with, without);
  EXPECT_LT(with, 0.5 * without);
}

}  // namespace
}  // namespace odonata::sysid
