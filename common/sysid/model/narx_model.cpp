#include "sysid/model/narx_model.hpp"

#include "sysid/model/narx_model_state.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "io/atomic_file.hpp"
#include "io/json_integer.hpp"
#include "metrics/accuracy.hpp"
#include "sysid/model/free_run.hpp"

namespace odonata::sysid {
namespace {
constexpr int kFormatVersion = 1;

}  // namespace

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

double NarxModel::Ndei(const Series& series, bool free_run) const {
  const Predictor predict = [this](const Eigen::VectorXd& x) { return Predict(x); };
  bool diverged = false;
  const Eigen::MatrixXd y_all = Targets(spec_, series);
  const Eigen::MatrixXd yhat = free_run && spec_.output_lags > 0
                                   ? SimulateFreeRun(spec_, series, predict, &diverged)
                                   : PredictOneStep(spec_, series, predict);
  if (diverged) return std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (int o = 0; o < outputs(); ++o) {
    sum += metrics::Score(y_all.col(o), yhat.col(o)).ndei;
  }
  const double ndei = sum / outputs();
  return std::isfinite(ndei) ? ndei : std::numeric_limits<double>::infinity();
}

double NarxModel::NdeiAhead(const Series& series, int horizon, int stride) const {
  if (horizon <= 0) return Ndei(series, true);
  if (horizon == 1 || spec_.output_lags == 0) return Ndei(series, false);
  const Predictor predict = [this](const Eigen::VectorXd& x) { return Predict(x); };
  bool diverged = false;
  Eigen::MatrixXd y_all = Targets(spec_, series);
  Eigen::MatrixXd yhat = PredictAhead(spec_, series, predict, horizon, &diverged, stride);
  if (diverged) return std::numeric_limits<double>::infinity();
  if (stride > 1) {
    // The rows PredictAhead predicted: every stride-th, counted back from the last.
    const Eigen::Index n = y_all.rows();
    const Eigen::Index kept = (n + stride - 1) / stride;
    Eigen::MatrixXd y_kept(kept, y_all.cols()), yhat_kept(kept, y_all.cols());
    for (Eigen::Index i = 0; i < kept; ++i) {
      y_kept.row(i) = y_all.row(n - 1 - (kept - 1 - i) * stride);
      yhat_kept.row(i) = yhat.row(n - 1 - (kept - 1 - i) * stride);
    }
    y_all = std::move(y_kept);
    yhat = std::move(yhat_kept);
  }
  double sum = 0.0;
  for (int o = 0; o < outputs(); ++o) sum += metrics::Score(y_all.col(o), yhat.col(o)).ndei;
  const double ndei = sum / outputs();
  return std::isfinite(ndei) ? ndei : std::numeric_limits<double>::infinity();
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
  return Predict(regressor, nullptr);
}

Eigen::VectorXd NarxModel::Predict(const Eigen::VectorXd& regressor,
                                   Eigen::VectorXd* linear_share) const {
  const Eigen::VectorXd x = scaling_.ScaleRegressor(regressor);
  Eigen::VectorXd y(outputs());
  if (linear_share) linear_share->setZero(outputs());
  for (int o = 0; o < outputs(); ++o) {
    const auto& m = models_[static_cast<std::size_t>(o)];
    double scaled = 0.0;
    if (envelope_.any()) {
      double distance = 0.0;
      const double fuzzy = m.PredictWithDistance(x, &distance);  // sets distance first
      const double share = envelope_.LinearShare(o, x, distance);
      scaled = envelope_.Blend(o, x, fuzzy, share);
      if (linear_share) (*linear_share)(o) = share;
    } else {
      scaled = m.Predict(x);
    }
    y(o) = limits_.Apply(o, scaling_.UnscaleOutput(o, scaled));
  }
  return y;
}

void NarxModel::SetEnvelope(const DataEnvelope& envelope) {
  const std::string p = envelope.Problems(outputs(), spec_.size());
  if (!p.empty()) throw std::invalid_argument(p);
  envelope_ = envelope;
}

void NarxModel::FitEnvelope(const Series& train) {
  const RegressionData d = BuildRegression(spec_, train);
  envelope_ =
      DataEnvelope::Fit(models_, scaling_.ScaleRegressorRows(d.x), scaling_.ScaleOutputRows(d.y));
}

void NarxModel::SetLimits(const OutputLimits& limits) {
  const std::string p = limits.Problems(outputs());
  if (!p.empty()) throw std::invalid_argument(p);
  limits_ = limits.any() ? limits : OutputLimits{};
}

int NarxModel::total_rules() const {
  int n = 0;
  for (const auto& m : models_) n += m.rules();
  return n;
}

NarxModelState NarxModel::State() const {
  NarxModelState s;
  s.spec = spec_;
  s.scaling = scaling_;
  s.limits = limits_;
  s.envelope = envelope_;
  for (const auto& m : models_) s.models.push_back(m.State());
  return s;
}

NarxModel NarxModel::FromState(const NarxModelState& s) {
  try {
    if (s.models.size() != s.spec.outputs.size()) {
      throw std::runtime_error("model count differs from the output count");
    }
    const std::string scaling = s.scaling.Problems();
    if (!scaling.empty()) throw std::runtime_error(scaling);
    NarxModel narx(s.spec, fuzzy::FuzzyModelConfig{});  // checks the regressor first
    narx.models_.clear();
    for (const auto& m : s.models) {
      if (m.config.inputs != s.spec.size()) {
        throw std::runtime_error("a model's input count differs from the regressor size");
      }
      narx.models_.push_back(fuzzy::FuzzyModel::FromState(m));
    }
    narx.SetScaling(s.scaling);
    narx.SetLimits(s.limits);
    narx.SetEnvelope(s.envelope);
    return narx;
  } catch (const std::invalid_argument& ex) {
    throw std::runtime_error(ex.what());
  }
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
  if (limits_.any()) j["output_limits"] = limits_.ToJson();
  if (envelope_.any()) j["data_envelope"] = envelope_.ToJson();
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
    if (io::JsonInteger<int>(j.at("version"), "version") != kFormatVersion) {
      throw std::runtime_error("unsupported model version " + j.at("version").dump());
    }
    NarxModelState s;
    const auto& r = j.at("regressor");
    s.spec.output_lags = io::JsonInteger<int>(r.at("output_lags"), "output_lags");
    s.spec.input_lags = io::JsonInteger<int>(r.at("input_lags"), "input_lags");
    s.spec.delay = io::JsonInteger<int>(r.at("delay"), "delay");
    s.spec.outputs = r.at("outputs").get<std::vector<std::string>>();
    s.spec.inputs = r.at("inputs").get<std::vector<std::string>>();
    const auto& models = j.at("models");
    // Checked before the models are read: a hostile file may hold millions.
    if (models.size() != s.spec.outputs.size()) {
      throw std::runtime_error("model count differs from the output count");
    }
    for (const auto& m : models) s.models.push_back(fuzzy::FuzzyModel::StateFromJson(m));
    s.scaling = Scaling::FromJson(j.at("scaling"));
    if (j.contains("output_limits"))
      s.limits =
          OutputLimits::FromJson(j.at("output_limits"), static_cast<int>(s.spec.outputs.size()));
    if (j.contains("data_envelope")) s.envelope = DataEnvelope::FromJson(j.at("data_envelope"));
    return FromState(s);
  } catch (const nlohmann::json::exception& ex) {
    throw std::runtime_error(ex.what());
  } catch (const std::invalid_argument& ex) {
    throw std::runtime_error(ex.what());
  }
}

bool NarxModel::Readable() const {
  try {
    (void)FromState(State());
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

namespace {

// What a model file keeps beside the model under `key` (null when absent): one reading for the
// sample time and the covariance, which the model itself never reads.
nlohmann::json SavedBesideTheModel(const std::string& path, const char* key) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    const auto it = j.find(key);
    return it == j.end() ? nlohmann::json() : *it;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace

double NarxModel::SavedSampleTime(const std::string& path) {
  const nlohmann::json ts = SavedBesideTheModel(path, "sample_time_s");
  if (!ts.is_number()) return 0.0;
  const double v = ts.get<double>();
  return std::isfinite(v) && v > 0 ? v : 0.0;
}

nlohmann::json NarxModel::SavedLocalCovariance(const std::string& path) {
  const nlohmann::json c = SavedBesideTheModel(path, "local_model_covariance");
  return c.is_object() ? c : nlohmann::json();
}

void NarxModel::Save(const std::string& path, double sample_time_s,
                     const nlohmann::json* local_model_covariance) const {
  nlohmann::json j = ToJson();
  if (std::isfinite(sample_time_s) && sample_time_s > 0) j["sample_time_s"] = sample_time_s;
  if (local_model_covariance && !local_model_covariance->is_null())
    j["local_model_covariance"] = *local_model_covariance;
  // A model its own reader refuses is not written: a learner that diverged wrote NaN as null,
  // which no program could read back, over the last good file.
  try {
    (void)FromJson(j);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": not written: the model holds a value no reader takes (" +
                             e.what() + ")");
  }
  // Whole or absent: a crash mid-write never leaves a truncated model behind.
  io::WriteFileAtomically(path, j.dump(1) + "\n");
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
