#include "sysid/model/rule_listing.hpp"

#include <cmath>
#include <cstdio>

#include "fuzzy/linear_consequent.hpp"
#include "fuzzy/singleton_consequent.hpp"
#include "sysid/model/local_dynamics.hpp"

namespace odonata::sysid {
namespace {
// Scaled widths above this leave a premise flat over the input's range [−1, 1].
constexpr double kFlatWidth = 10.0;
}  // namespace

std::string LinguisticLabel(double c) {
  // A centre beyond the declared range still sits at that end of the data: "above range (≈1.87)"
  // read as if the rule were outside what the vehicle does.
  if (c < -0.6) return "very low";
  if (c < -0.2) return "low";
  if (c <= 0.2) return "medium";
  if (c <= 0.6) return "high";
  return "very high";
}

std::vector<std::string> DescribeRules(const NarxModel& model, int output, double sample_time_s) {
  const auto& fm = model.model(output);
  const auto& rb = fm.rule_base();
  const auto& sc = model.scaling();
  const auto names = model.spec().RegressorNames();
  const std::string target = model.spec().TargetName(output);
  const int n = fm.inputs();
  std::vector<std::string> lines;
  const bool one = rb.rules() == 1;  // fires fully everywhere: the model is its consequent
  for (int j = 0; j < rb.rules(); ++j) {
    // An expert's words where the rule has them (a .fis's names), the band's label elsewhere.
    const fuzzy::RuleNames& given = fm.names(j);
    std::string s = one ? "" : "IF ";
    bool first = true;
    for (int i = 0; i < n && !one; ++i) {
      // A premise ten times wider than the input's range ("don't care" in a .fis) changes the
      // firing by under 2 % anywhere in it: the rule does not depend on that input.
      if (rb.sigma(j, i) > kFlatWidth) continue;
      const double c = rb.centre(j, i);
      const double raw = sc.regressor_mid(i) + sc.regressor_half(i) * c;
      const double width = sc.regressor_half(i) * rb.sigma(j, i);
      const auto k = static_cast<std::size_t>(i);
      const std::string term =
          k < given.terms.size() && !given.terms[k].empty() ? given.terms[k] : LinguisticLabel(c);
      s += (first ? "" : " AND ") + names[k] + " is " + term + " (≈" + SentenceNumber(raw) + " ±" +
           SentenceNumber(width) + ")";
      first = false;
    }
    if (!one && first) s += "always";  // every input left out
    if (fm.consequent().kind() == fuzzy::ConsequentKind::kSingleton) {
      const auto& cons = static_cast<const fuzzy::SingletonConsequent&>(fm.consequent());
      const std::string value = SentenceNumber(sc.UnscaleOutput(output, cons.centre(j)));
      s += one ? target + " = " + value + " (one rule: a constant)"
               : " THEN " + target + " is ≈" + value;
    } else {
      const std::string text = DescribeLinearModel(
          model.spec(), output, RuleLinearModel(model, output, j), sample_time_s);
      if (one) {
        // "y = c + … (one rule: a linear model, as ARX) — dynamics", as it always read.
        const auto dash = text.find(" — ");
        s += target + " = " + text.substr(0, dash) + " (one rule: a linear model, as ARX)" +
             (dash == std::string::npos ? "" : text.substr(dash));
      } else {
        s += " THEN " + target + " ≈ " + text;
      }
    }
    if (!given.output.empty()) s += " [" + given.output + "]";
    lines.push_back(s);
  }
  return lines;
}

std::string DescribeLinearModel(const RegressorSpec& spec, int output, const RawLinearModel& raw,
                                double sample_time_s) {
  const auto names = spec.RegressorNames();
  std::string s = SentenceNumber(raw.constant);
  for (Eigen::Index i = 0; i < raw.coefficients.size(); ++i) {
    const double k = raw.coefficients(i);
    s += (k < 0 ? " - " : " + ") + SentenceNumber(std::abs(k)) + "·" +
         names[static_cast<std::size_t>(i)];
  }
  // A dynamic local model: how fast and how much, in the control engineer's terms.
  if (spec.output_lags > 0)
    s += " — " + DescribeDynamics(AnalyseDynamics(spec, output, raw, sample_time_s), sample_time_s);
  return s;
}

}  // namespace odonata::sysid
