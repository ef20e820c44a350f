// Preconditions hold in every build, Release and the NDEBUG sanitizer build included: a caller's
// bug stops the process with the file, the line and the condition.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "contract/precondition.hpp"
#include "fuzzy/gaussian_rule_base.hpp"

namespace odonata::fuzzy {
namespace {

TEST(PreconditionDeathTest, AViolationAbortsNamingTheCondition) {
  EXPECT_DEATH(ODONATA_EXPECTS(1 + 1 == 3),
               "precondition_test.cpp:[0-9]+: precondition failed: 1 \\+ 1 == 3");
  EXPECT_DEATH(GaussianRuleBase(0, 4), "precondition failed: inputs >= 1");
  GaussianRuleBase rules(2, 4);
  // A regressor of the wrong size would have been read past its end with assert compiled out.
  Inference inference;
  EXPECT_DEATH(rules.Evaluate(Eigen::VectorXd::Zero(3), &inference),
               "precondition failed: x.size\\(\\) == inputs_");
}

}  // namespace
}  // namespace odonata::fuzzy
