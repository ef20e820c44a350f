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

nlohmann::json ScoreToJson(const Accuracy& a) {
  nlohmann::json j = AccuracyToJson(a);
  if (FitDiverges(a.fit_percent)) j["diverged"] = true;
  return j;
}

}  // namespace odonata::metrics
