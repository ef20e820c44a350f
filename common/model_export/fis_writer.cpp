#include "model_export/fis_writer.hpp"

#include <sstream>

#include "model_export/exact_number.hpp"

namespace odonata::model_export {
namespace {

std::string Vector(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? " " : "") + ExactNumber(v[i]);
  return s + "]";
}

}  // namespace

std::string ToFis(const inference::TskModel& m) {
  // Each rule has its own membership function on every input (MF j of input i is rule j's), the
  // layout an evolving model has: rules share no terms.
  std::ostringstream o;
  const std::size_t n = m.inputs(), r = m.rules.size();
  o << "% Written by odonata (docs/model_export.md): raw units, one rule per membership index.\n"
    << "[System]\nName='" << m.name << "'\nType='sugeno'\nVersion=2.0\nNumInputs=" << n
    << "\nNumOutputs=1\nNumRules=" << r
    << "\nAndMethod='prod'\nOrMethod='probor'\nImpMethod='prod'\nAggMethod='sum'\n"
       "DefuzzMethod='wtaver'\n";
  for (std::size_t i = 0; i < n; ++i) {
    o << "\n[Input" << i + 1 << "]\nName='" << m.input_names[i]
      << "'\nRange=" << Vector({m.input_low[i], m.input_high[i]}) << "\nNumMFs=" << r << "\n";
    for (std::size_t j = 0; j < r; ++j)
      o << "MF" << j + 1 << "='r" << j + 1 << "':'gaussmf',"
        << Vector({m.rules[j].sigma[i], m.rules[j].centre[i]}) << "\n";
  }
  o << "\n[Output1]\nName='" << m.output_name
    << "'\nRange=" << Vector({m.output_low, m.output_high}) << "\nNumMFs=" << r << "\n";
  for (std::size_t j = 0; j < r; ++j)
    o << "MF" << j + 1 << "='r" << j + 1 << "':'" << (m.linear ? "linear" : "constant") << "',"
      << Vector(m.rules[j].coefficients) << "\n";
  o << "\n[Rules]\n";
  for (std::size_t j = 0; j < r; ++j) {
    for (std::size_t i = 0; i < n; ++i) o << (i ? " " : "") << j + 1;
    o << ", " << j + 1 << " (" << ExactNumber(m.rules[j].weight) << ") : 1\n";
  }
  return o.str();
}

}  // namespace odonata::model_export
