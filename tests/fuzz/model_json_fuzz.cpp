// Fuzz harness: model files (odonata-fit --load-model, odonata-identifier --model). A model
// that loads must also predict and save without a crash; a bad one must be an exception.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "sysid/model/narx_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const nlohmann::json j = nlohmann::json::parse(data, data + size, nullptr, false);
  if (j.is_discarded()) return 0;
  try {
    const odonata::sysid::NarxModel m = odonata::sysid::NarxModel::FromJson(j);
    const Eigen::VectorXd x = Eigen::VectorXd::Constant(m.spec().size(), 0.1);
    (void)m.Predict(x);
    (void)m.ToJson().dump();
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
