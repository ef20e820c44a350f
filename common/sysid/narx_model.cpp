#include "sysid/narx_model.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace odonata::sysid {
namespace {
constexpr int kFormatVersion = 1;
}

NarxModel::NarxModel(const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base) : spec_(spec) {
  const std::string problems = spec.Problems();
  if (!problems.empty()) throw std::invalid_argument("regressor: " + problems);
  fuzzy::FuzzyModelConfig cfg = base;
  cfg.inputs = spec.size();
  for (std::size_t o = 0; o < spec.outputs.size(); ++o) models_.emplace_back(cfg);
  scaling_.regressor_mid = Eigen::VectorXd::Zero(cfg.inputs);
  scaling_.regressor_half = Eigen::VectorXd::Ones(cfg.inputs);
  scaling_.output_mean = Eigen::VectorXd::Zero(outputs());
  scaling_.output_std = Eigen::VectorXd::Ones(outputs());
}

void NarxModel::FitScaling(const Series& train) {
  const RegressionData d = BuildRegression(spec_, train);
  scaling_ = Scaling::FromData(d.x, d.y);
}

void NarxModel::SetScaling(const Scaling& scaling) {
  if (scaling.regressor_mid.size() != spec_.size() || scaling.output_mean.size() != outputs()) {
    throw std::invalid_argument("scaling does not match the regressor (" +
                                std::to_string(spec_.size()) + " regressors, " +
                                std::to_string(outputs()) + " outputs)");
  }
  scaling_ = scaling;
}

void NarxModel::Train(const Series& train, const TrainOptions& options) {
  const RegressionData d = BuildRegression(spec_, train);
  if (options.fit_scaling) scaling_ = Scaling::FromData(d.x, d.y);
  const Eigen::Index rows = d.x.rows();
  Eigen::MatrixXd xs(rows, d.x.cols());
  Eigen::MatrixXd ys(rows, d.y.cols());
  for (Eigen::Index r = 0; r < rows; ++r) {
    xs.row(r) = scaling_.ScaleRegressor(d.x.row(r).transpose()).transpose();
    for (int o = 0; o < outputs(); ++o) ys(r, o) = scaling_.ScaleOutput(o, d.y(r, o));
  }
  for (int epoch = 0; epoch < options.epochs; ++epoch) {
    fuzzy::LearnMode mode = epoch == 0 ? fuzzy::LearnMode::kGrowAndTune : fuzzy::LearnMode::kTune;
    // Once least squares owns the consequents, later passes only move the antecedents: an online
    // consequent update would only pull them away from the optimum just solved.
    if (epoch > 0 && options.refine_least_squares) mode = fuzzy::LearnMode::kTunePremises;
    for (Eigen::Index r = 0; r < rows; ++r) {
      const Eigen::VectorXd x = xs.row(r).transpose();
      for (int o = 0; o < outputs(); ++o)
        models_[static_cast<std::size_t>(o)].Learn(x, ys(r, o), mode);
      if (options.progress && (r % 1024 == 0 || r + 1 == rows))
        options.progress(epoch, r + 1, rows);
    }
    if (options.refine_least_squares) {
      for (int o = 0; o < outputs(); ++o) {
        models_[static_cast<std::size_t>(o)].RefineConsequents(xs, ys.col(o), options.ridge);
      }
    }
  }
}

std::vector<fuzzy::LearnResult> NarxModel::Learn(const Eigen::VectorXd& regressor,
                                                 const Eigen::VectorXd& targets,
                                                 fuzzy::LearnMode mode) {
  const Eigen::VectorXd x = scaling_.ScaleRegressor(regressor);
  std::vector<fuzzy::LearnResult> results;
  results.reserve(models_.size());
  for (int o = 0; o < outputs(); ++o) {
    auto r =
        models_[static_cast<std::size_t>(o)].Learn(x, scaling_.ScaleOutput(o, targets(o)), mode);
    r.prediction = scaling_.UnscaleOutput(o, r.prediction);
    r.error *= scaling_.output_std(o);
    results.push_back(r);
  }
  return results;
}

Eigen::VectorXd NarxModel::Predict(const Eigen::VectorXd& regressor) const {
  const Eigen::VectorXd x = scaling_.ScaleRegressor(regressor);
  Eigen::VectorXd y(outputs());
  for (int o = 0; o < outputs(); ++o) {
    y(o) = scaling_.UnscaleOutput(o, models_[static_cast<std::size_t>(o)].Predict(x));
  }
  return y;
}

int NarxModel::total_rules() const {
  int n = 0;
  for (const auto& m : models_) n += m.rules();
  return n;
}

nlohmann::json NarxModel::ToJson() const {
  nlohmann::json j;
  j["format"] = "odonata-narx-fuzzy";
  j["version"] = kFormatVersion;
  j["regressor"] = {{"output_lags", spec_.output_lags},
                    {"input_lags", spec_.input_lags},
                    {"delay", spec_.delay},
                    {"outputs", spec_.outputs},
                    {"inputs", spec_.inputs}};
  j["scaling"] = scaling_.ToJson();
  nlohmann::json models = nlohmann::json::array();
  for (const auto& m : models_) models.push_back(m.ToJson());
  j["models"] = models;
  return j;
}

NarxModel NarxModel::FromJson(const nlohmann::json& j) {
  try {
    if (j.value("format", "") != "odonata-narx-fuzzy") {
      throw std::runtime_error("not an odonata model (missing \"format\": \"odonata-narx-fuzzy\")");
    }
    if (j.at("version").get<int>() != kFormatVersion) {
      throw std::runtime_error("unsupported model version " + j.at("version").dump());
    }
    RegressorSpec spec;
    const auto& r = j.at("regressor");
    spec.output_lags = r.at("output_lags").get<int>();
    spec.input_lags = r.at("input_lags").get<int>();
    spec.delay = r.at("delay").get<int>();
    spec.outputs = r.at("outputs").get<std::vector<std::string>>();
    spec.inputs = r.at("inputs").get<std::vector<std::string>>();
    const auto& models = j.at("models");
    if (models.size() != spec.outputs.size()) {
      throw std::runtime_error("model count differs from the output count");
    }
    fuzzy::FuzzyModelConfig cfg;
    NarxModel narx(spec, cfg);
    narx.models_.clear();
    for (const auto& m : models) {
      narx.models_.push_back(fuzzy::FuzzyModel::FromJson(m));
      if (narx.models_.back().inputs() != spec.size()) {
        throw std::runtime_error("a model's input count differs from the regressor size");
      }
    }
    narx.SetScaling(Scaling::FromJson(j.at("scaling")));
    return narx;
  } catch (const nlohmann::json::exception& ex) {
    throw std::runtime_error(ex.what());
  } catch (const std::invalid_argument& ex) {
    throw std::runtime_error(ex.what());
  }
}

void NarxModel::Save(const std::string& path) const {
  // Write then rename, so a crash mid-write never leaves a truncated model behind.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot write (" + std::strerror(errno) + ")");
    out << ToJson().dump(1) << '\n';
    out.flush();
    if (!out) throw std::runtime_error(path + ": write failed");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    throw std::runtime_error(path + ": cannot rename from " + tmp + " (" + std::strerror(errno) +
                             ")");
  }
}

NarxModel NarxModel::Load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open model (" + std::strerror(errno) + ")");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& ex) {
    throw std::runtime_error(path + ": not valid JSON: " + ex.what());
  }
  try {
    return FromJson(j);
  } catch (const std::exception& ex) {
    throw std::runtime_error(path + ": " + ex.what());
  }
}

}  // namespace odonata::sysid
