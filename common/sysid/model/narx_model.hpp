#pragma once
// A NARX entropy fuzzy model in raw units: regressor spec + scaling + one fuzzy model per output.

#include <atomic>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "fuzzy/fuzzy_model.hpp"
#include "sysid/model/data_envelope.hpp"
#include "sysid/model/output_limits.hpp"
#include "sysid/model/regressor_spec.hpp"
#include "sysid/model/scaling.hpp"

namespace odonata::sysid {

/// One or several outputs identified over one shared regressor.
struct NarxModelState;  // narx_model_state.hpp

class NarxModel {
 public:
  /// `base.inputs` is overwritten with spec.size().
  /// @throws std::invalid_argument if the spec has problems.
  NarxModel(const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base);

  /// Scaling from the training series (regressor ranges, output mean and std), as used offline.
  void FitScaling(const Series& train);
  /// Scaling declared up front (online use, where the data is not known in advance).
  void SetScaling(const Scaling& scaling);

  /// Mean over outputs of the NDEI on `series` (free run if asked and there are output lags,
  /// else one step); +∞ when the simulation diverges.
  double Ndei(const Series& series, bool free_run) const;
  /// The same, `horizon` steps ahead (PredictAhead); 0 is free run, 1 one step. `stride` m > 1
  /// scores K steps ahead on every m-th target only (PredictAhead's stride), at 1/m of the cost.
  double NdeiAhead(const Series& series, int horizon, int stride = 1) const;

  /// One online step on a raw regressor and the raw targets (one per output).
  std::vector<fuzzy::LearnResult> Learn(const Eigen::VectorXd& regressor,
                                        const Eigen::VectorXd& targets,
                                        fuzzy::LearnMode mode = fuzzy::LearnMode::kGrowAndTune);
  /// Raw predicted outputs for a raw regressor.
  Eigen::VectorXd Predict(const Eigen::VectorXd& regressor) const;
  /// The same, and per output the share of the global linear model in it (0 inside the data's
  /// envelope, 1 well outside; DataEnvelope) in `linear_share` (sized outputs()).
  Eigen::VectorXd Predict(const Eigen::VectorXd& regressor, Eigen::VectorXd* linear_share) const;

  const RegressorSpec& spec() const { return spec_; }
  const Scaling& scaling() const { return scaling_; }
  /// Saturation limits every prediction is held to (empty: none).
  const OutputLimits& limits() const { return limits_; }
  /// @throws std::invalid_argument when they do not fit the outputs.
  void SetLimits(const OutputLimits& limits);
  const fuzzy::FuzzyModel& model(int output) const {
    return models_.at(static_cast<std::size_t>(output));
  }
  fuzzy::FuzzyModel& mutable_model(int output) {
    return models_.at(static_cast<std::size_t>(output));
  }
  /// Where the training data ends, and the linear model predictions blend into beyond it
  /// (DataEnvelope): set by Train, empty for a model that has not been trained offline.
  const DataEnvelope& envelope() const { return envelope_; }
  /// @throws std::invalid_argument when it does not fit the outputs and regressor.
  void SetEnvelope(const DataEnvelope& envelope);
  /// The envelope of the model as it is over the rows of `train` (what Train does last with
  /// TrainOptions::fit_envelope), for a model trained elsewhere.
  void FitEnvelope(const Series& train);
  int outputs() const { return static_cast<int>(models_.size()); }
  int total_rules() const;

  /// The whole model as plain data (narx_model_state.hpp), and back: FromState() is the one
  /// place a saved or received model is checked (regressor, scaling, every fuzzy model).
  /// @throws std::runtime_error naming what is wrong.
  NarxModelState State() const;
  static NarxModel FromState(const NarxModelState& state);
  /// Its state passes the reader's checks (FromState): every value finite and within the bounds a
  /// learner keeps to, so it predicts finitely on inputs of its range. A copy: not per sample.
  bool Readable() const;

  nlohmann::json ToJson() const;
  /// @throws std::runtime_error naming what is wrong.
  static NarxModel FromJson(const nlohmann::json& j);
  /// Writes the model; a known sample time (seconds, > 0) goes with it as "sample_time_s", so
  /// that what reads the file (odonata-export's local models) keeps time in seconds. Each rule's
  /// parameter covariance, when the writer knows it (odonata-fit, from its training data;
  /// LocalCovariancesToJson), goes with it as "local_model_covariance": the model never reads it.
  void Save(const std::string& path, double sample_time_s = 0.0,
            const nlohmann::json* local_model_covariance = nullptr) const;
  /// The "local_model_covariance" a model file was saved with (null: none).
  /// @throws std::runtime_error naming the file when it cannot be read.
  static nlohmann::json SavedLocalCovariance(const std::string& path);
  /// @throws std::runtime_error naming the file and the problem.
  static NarxModel Load(const std::string& path);
  /// The sample time a model file was saved with (seconds; 0: not known).
  /// @throws std::runtime_error naming the file when it cannot be read.
  static double SavedSampleTime(const std::string& path);

 private:
  // Offline estimation (sysid/estimation/narx_training.hpp) sets the whole model at once.
  friend class NarxTrainer;
  RegressorSpec spec_;
  Scaling scaling_;
  OutputLimits limits_;
  DataEnvelope envelope_;
  std::vector<fuzzy::FuzzyModel> models_;
};

}  // namespace odonata::sysid
