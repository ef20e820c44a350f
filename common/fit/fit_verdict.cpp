#include "fit/fit_verdict.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "sysid/model/free_run.hpp"

namespace odonata::fit {
namespace {

// "73.90 %", or "diverges".
std::string Percent(const nlohmann::json& block) {
  if (block.is_null() || !block.contains("fit")) return "–";
  if (block.value("diverged", false)) return "diverges";
  if (!block["fit"].is_number()) return "–";
  char s[32];
  std::snprintf(s, sizeof s, "%.2f %%", block["fit"].get<double>());
  return s;
}

const char* ModeWords(const std::string& mode) {
  return mode == "k_step" ? "steps ahead" : mode == "free_run" ? "free run" : "one step ahead";
}

// The model's one-step predictions on `series` hardly move where the data does: a constant.
bool IsConstant(const sysid::NarxModel& model, const sysid::Series& series) {
  const sysid::Predictor predict = [&model](const Eigen::VectorXd& x) { return model.Predict(x); };
  const Eigen::MatrixXd yhat = sysid::PredictOneStep(model.spec(), series, predict);
  const Eigen::MatrixXd y = sysid::Targets(model.spec(), series);
  if (yhat.rows() < 2) return false;
  const auto spread = [](const Eigen::VectorXd& v) {
    return std::sqrt((v.array() - v.mean()).square().mean());
  };
  return spread(yhat.col(0)) <= 1e-6 * spread(y.col(0));
}

}  // namespace

nlohmann::json Verdict(const nlohmann::json& r, const sysid::NarxModel& model,
                       const sysid::Series& series) {
  const std::string data = r.contains("validate") ? "validate" : "train";
  const nlohmann::json& scores = r[data];
  const std::string mode = scores.contains("k_step")     ? "k_step"
                           : scores.contains("free_run") ? "free_run"
                                                         : "one_step";
  const auto baseline = [&](const char* name) -> nlohmann::json {
    if (!r.contains("baselines") || !r["baselines"].contains(name)) return nullptr;
    const auto& b = r["baselines"][name];
    return b.contains(data) && b[data].contains(mode) ? b[data][mode] : nlohmann::json();
  };
  nlohmann::json v;
  v["data"] = data;
  v["mode"] = mode;
  v["fit"] = scores[mode];
  v["arx"] = baseline("arx");
  v["persistence"] = baseline("persistence");
  v["flags"] = nlohmann::json::array();
  std::string text = data == "validate" ? "validation, " : "training file (no validation), ";
  if (mode == "k_step") text += std::to_string(scores[mode].value("horizon", 0)) + " ";
  text += std::string(ModeWords(mode)) + ": FIT " + Percent(scores[mode]) + " (ARX " +
          Percent(v["arx"]) + ", persistence " + Percent(v["persistence"]) + ")";
  if (IsConstant(model, series)) {
    v["flags"].push_back("constant");
    text += "; the model is a constant: it has identified nothing";
  }
  const auto fit = [](const nlohmann::json& b) {
    return b.is_object() && b.contains("fit") && b["fit"].is_number() && !b.value("diverged", false)
               ? b["fit"].get<double>()
               : NAN;
  };
  const double fm = fit(scores[mode]), fp = fit(v["persistence"]), fa = fit(v["arx"]);
  if (std::isfinite(fp) && (scores[mode].value("diverged", false) || fm < fp)) {
    v["flags"].push_back("below_persistence");
    text += "; below persistence: holding the last value predicts better";
  } else if (std::isfinite(fa) && fm < fa - 0.01) {
    v["flags"].push_back("below_arx");
    text += "; below ARX: the linear model predicts better";
  }
  v["text"] = text;
  return v;
}

}  // namespace odonata::fit
