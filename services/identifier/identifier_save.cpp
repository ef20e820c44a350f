// The identifier's model file: the model as it is after any closing refit, and beside it each
// rule's parameter covariance on the samples it kept (odonata-export's local models take it).
#include <cstdio>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "identifier_node.hpp"
#include "sysid/estimation/local_model_uncertainty.hpp"

namespace odonata::identifier {

void IdentifierNode::SaveModel(const std::string& path) {
  if (path.empty()) throw std::invalid_argument("SAVE_MODEL without a path (and no --save-model)");
  core_.Settle();  // a closing refit after a freeze is the model to save (waits for it)
  RefitLanded();
  // Each rule's parameter covariance on the samples kept for the refits (odonata-export's local
  // models take it); none when it keeps none or too few for a regressor.
  nlohmann::json covariance;
  try {
    covariance = sysid::LocalCovariancesToJson(core_.model(), core_.KeptSeries(), 0.0);
  } catch (const std::invalid_argument&) {
  }
  core_.model().Save(path, 0.0, &covariance);
  std::fprintf(stderr, "[%s] model saved to %s (%d rules, %lld samples learned)\n",
               config_.instance.c_str(), path.c_str(), core_.model().total_rules(),
               static_cast<long long>(core_.samples_learned()));
}

}  // namespace odonata::identifier
