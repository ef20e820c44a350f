#pragma once
// The model the export tests exchange: a few dozen rules on Narendra's plant, as odonata-fit's
// selection picks there, with output widths other than 1 so the rule weights they export as are
// exercised (Octave, fuzzylite and the .fis import must all apply them).

#include "../sysid/narendra_series.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::model_export::testing {

inline sysid::NarxModel TrainedNarendraModel(
    fuzzy::ConsequentKind kind = fuzzy::ConsequentKind::kLinear, bool uneven_output_widths = true) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = kind;
  cfg.entropy.threshold = 0.49;
  sysid::NarxModel m(sysid::testing::NarendraSpec(), cfg);
  sysid::TrainOptions o;
  o.epochs = 2;
  Train(m, sysid::testing::NarendraTrain(2000), o);
  if (uneven_output_widths) {
    auto& rb = m.mutable_model(0).mutable_rule_base();
    for (int j = 0; j < rb.rules(); ++j) rb.set_output_width(j, 0.6 + 0.05 * (j % 9));
  }
  return m;
}

}  // namespace odonata::model_export::testing
