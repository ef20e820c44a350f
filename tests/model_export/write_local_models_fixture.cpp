// Writes what octave_local_models_test.sh checks Octave's control package against: a model of
// Narendra's plant with two output and two input lags and several linear rules (model.json), and
// odonata's own figures for each rule (expected.json): poles (sysid::AnalyseDynamics), steady-
// state gains and 40 samples of the step response from each signal (the rule's own recursion).

#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "../sysid/narendra_series.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/local_dynamics.hpp"
#include "sysid/model/narx_model.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: write_local_models_fixture DIR\n";
    return 2;
  }
  using namespace odonata;
  const std::string dir = argv[1];
  sysid::RegressorSpec spec = sysid::testing::NarendraSpec();
  spec.output_lags = 2;
  spec.input_lags = 2;
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  cfg.entropy.threshold = 0.45;
  sysid::NarxModel m(spec, cfg);
  sysid::TrainOptions o;
  o.epochs = 2;
  Train(m, sysid::testing::NarendraTrain(2000), o);
  m.Save(dir + "/model.json");
  nlohmann::json expected = nlohmann::json::array();
  for (int j = 0; j < m.model(0).rules(); ++j) {
    const sysid::RawLinearModel raw = sysid::RuleLinearModel(m, 0, j);
    const sysid::LocalDynamics d = sysid::AnalyseDynamics(spec, 0, raw, 0.0);
    nlohmann::json rule;
    for (const auto& p : d.poles) rule["poles"].push_back({p.real(), p.imag()});
    for (std::size_t e = 0; e < d.dc_gain.size(); ++e) {
      rule["dcgain"].push_back(d.dc_gain[e].second);
      rule["step"].push_back(sysid::StepResponse(spec, 0, raw, static_cast<int>(e), 40));
    }
    expected.push_back(rule);
  }
  std::ofstream(dir + "/expected.json") << expected.dump() << "\n";
  std::cout << m.total_rules() << " rules\n";
  return m.total_rules() >= 2 ? 0 : 1;
}
