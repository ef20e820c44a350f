#include "model_export/fll_writer.hpp"

#include <sstream>

#include "model_export/exact_number.hpp"

namespace odonata::model_export {
std::string ToFll(const inference::TskModel& m) {
  std::ostringstream o;
  const std::size_t n = m.inputs(), r = m.rules.size();
  o << "Engine: " << m.name << "\n"
    << "  description: written by odonata (docs/model_export.md), raw units\n";
  for (std::size_t i = 0; i < n; ++i) {
    o << "InputVariable: " << m.input_names[i]
      << "\n  enabled: true\n  range: " << ExactNumber(m.input_low[i]) << " "
      << ExactNumber(m.input_high[i]) << "\n  lock-range: false\n";
    for (std::size_t j = 0; j < r; ++j)
      o << "  term: r" << j + 1 << " Gaussian " << ExactNumber(m.rules[j].centre[i]) << " "
        << ExactNumber(m.rules[j].sigma[i]) << "\n";
  }
  o << "OutputVariable: " << m.output_name
    << "\n  enabled: true\n  range: " << ExactNumber(m.output_low) << " "
    << ExactNumber(m.output_high)
    << "\n  lock-range: false\n  aggregation: none\n  defuzzifier: WeightedAverage TakagiSugeno\n"
       "  default: nan\n  lock-previous: false\n";
  for (std::size_t j = 0; j < r; ++j) {
    o << "  term: r" << j + 1 << (m.linear ? " Linear" : " Constant");
    for (const double c : m.rules[j].coefficients) o << " " << ExactNumber(c);
    o << "\n";
  }
  o << "RuleBlock: rules\n  enabled: true\n  conjunction: AlgebraicProduct\n  disjunction: none\n"
       "  implication: none\n  activation: General\n";
  for (std::size_t j = 0; j < r; ++j) {
    o << "  rule: if ";
    for (std::size_t i = 0; i < n; ++i)
      o << (i ? " and " : "") << m.input_names[i] << " is r" << j + 1;
    o << " then " << m.output_name << " is r" << j + 1 << " with " << ExactNumber(m.rules[j].weight)
      << "\n";
  }
  return o.str();
}

}  // namespace odonata::model_export
