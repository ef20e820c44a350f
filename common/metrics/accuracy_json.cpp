#include "metrics/accuracy_json.hpp"

#include <cmath>

namespace odonata::metrics {

nlohmann::json AccuracyToJson(const Accuracy& a) {
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  return {{"fit", num(a.fit_percent)},
          {"vaf", num(a.vaf_percent)},
          {"rmse", num(a.rmse)},
          {"ndei", num(a.ndei)},
          {"samples", a.samples}};
}

}  // namespace odonata::metrics
