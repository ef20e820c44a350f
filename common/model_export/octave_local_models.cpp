#include "model_export/octave_local_models.hpp"

#include <cstdio>
#include <sstream>

#include "sysid/model/local_dynamics.hpp"

namespace odonata::model_export {
namespace {

std::string ExactNumber(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// An Octave matrix literal; an empty one keeps its shape (zeros(r, c)).
std::string OctaveMatrix(const Eigen::MatrixXd& m) {
  if (m.size() == 0)
    return "zeros(" + std::to_string(m.rows()) + ", " + std::to_string(m.cols()) + ")";
  std::string s = "[";
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) s += (c ? " " : "") + ExactNumber(m(r, c));
    s += r + 1 < m.rows() ? "; " : "";
  }
  return s + "]";
}

// A single-quoted Octave string ('' for a quote).
std::string OctaveString(const std::string& text) {
  std::string s = "'";
  for (const char c : text) s += c == '\'' ? std::string("''") : std::string(1, c);
  return s + "'";
}

// Rule j's covariance from the model file's "local_model_covariance", as an Octave literal: [] when
// absent or not a p × p matrix of numbers.
std::string RuleCovariance(const nlohmann::json& all, const std::string& output, int rule,
                           std::size_t p) {
  if (!all.is_object() || !all.contains(output) || !all[output].is_array() ||
      static_cast<std::size_t>(rule) >= all[output].size())
    return "[]";
  const auto& rows = all[output][static_cast<std::size_t>(rule)];
  if (!rows.is_array() || rows.size() != p) return "[]";
  Eigen::MatrixXd m(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(p));
  for (std::size_t r = 0; r < p; ++r) {
    if (!rows[r].is_array() || rows[r].size() != p) return "[]";
    for (std::size_t c = 0; c < p; ++c) {
      if (!rows[r][c].is_number()) return "[]";
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = rows[r][c].get<double>();
    }
  }
  return OctaveMatrix(m);
}

}  // namespace

std::string OctaveLocalModels(const sysid::NarxModel& model, const std::vector<int>& outputs,
                              double sample_time_s, const std::string& source,
                              const nlohmann::json& covariance) {
  std::ostringstream o;
  o << "% Each rule's linear local model of " << source << " as a discrete state-space model\n"
    << "% (odonata-export --local-models): x(t+1) = A x(t) + B v(t), y(t) = C x(t) + D v(t) + "
       "offset,\n"
    << "% v the signals named in `signals`, about rest; time in "
    << (sample_time_s > 0 ? "seconds" : "samples (Ts = 1: no sample time given)") << ".\n"
    << "% Run it (source or run) to get local_models(k).sys, an octave-control ss object.\n"
    << "% covariance: the rule's parameter covariance (raw units) in the order `parameters` "
       "names,\n"
    << "% from its training data (odonata-fit --save-model); [] where the file holds none.\n"
    << "pkg load control\n"
    << "local_models = struct('output', {}, 'rule', {}, 'A', {}, 'B', {}, 'C', {}, 'D', {}, "
       "'Ts', {}, 'offset', {}, 'signals', {}, 'sys', {}, 'parameters', {}, 'covariance', {});\n"
    << "Ts = " << ExactNumber(sample_time_s > 0 ? sample_time_s : 1.0) << ";\n";
  const std::vector<std::string> regressors = model.spec().RegressorNames();
  std::string parameters = "{'1'";
  for (const auto& r : regressors) parameters += ", " + OctaveString(r);
  parameters += "}";
  const std::size_t p = regressors.size() + 1;
  for (const int out : outputs) {
    const std::string& name = model.spec().outputs[static_cast<std::size_t>(out)];
    for (int j = 0; j < model.model(out).rules(); ++j) {
      const auto ss = sysid::StateSpace(model.spec(), out, sysid::RuleLinearModel(model, out, j));
      std::string signals = "{";
      for (std::size_t e = 0; e < ss.signals.size(); ++e)
        signals += (e ? ", " : "") + OctaveString(ss.signals[e]);
      signals += "}";
      o << "k = numel(local_models) + 1;\n"
        << "local_models(k).output = "
        << OctaveString(model.spec().outputs[static_cast<std::size_t>(out)]) << ";\n"
        << "local_models(k).rule = " << j + 1 << ";\n"
        << "local_models(k).A = " << OctaveMatrix(ss.a) << ";\n"
        << "local_models(k).B = " << OctaveMatrix(ss.b) << ";\n"
        << "local_models(k).C = " << OctaveMatrix(ss.c) << ";\n"
        << "local_models(k).D = " << OctaveMatrix(ss.d) << ";\n"
        << "local_models(k).Ts = Ts;\n"
        << "local_models(k).offset = " << ExactNumber(ss.offset) << ";\n"
        << "local_models(k).signals = " << signals << ";\n"
        << "local_models(k).sys = ss(local_models(k).A, local_models(k).B, local_models(k).C, "
           "local_models(k).D, Ts);\n"
        << "local_models(k).parameters = " << parameters << ";\n"
        << "local_models(k).covariance = " << RuleCovariance(covariance, name, j, p) << ";\n";
    }
  }
  return o.str();
}

}  // namespace odonata::model_export
