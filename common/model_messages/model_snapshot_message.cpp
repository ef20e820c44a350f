#include "model_messages/model_snapshot_message.hpp"

#include <stdexcept>

#include <nlohmann/json.hpp>

namespace odonata::model_messages {
odonata::model_snapshot_t EncodeSnapshot(const sysid::NarxModel& model) {
  const nlohmann::json j = model.ToJson();
  odonata::model_snapshot_t m;
  m.utime = 0;
  m.seq = 0;
  m.samples_learned = 0;
  m.learning = 1;  // the identifier sets both from its learner
  const auto& r = j["regressor"];
  m.output_lags = r["output_lags"];
  m.input_lags = r["input_lags"];
  m.delay = r["delay"];
  m.outputs = r["outputs"].get<std::vector<std::string>>();
  m.num_outputs = static_cast<int32_t>(m.outputs.size());
  m.inputs = r["inputs"].get<std::vector<std::string>>();
  m.num_inputs = static_cast<int32_t>(m.inputs.size());
  const auto& s = j["scaling"];
  m.regressor_mid = s["regressor_mid"].get<std::vector<double>>();
  m.regressor_half = s["regressor_half"].get<std::vector<double>>();
  m.num_regressors = static_cast<int32_t>(m.regressor_mid.size());
  m.output_mean = s["output_mean"].get<std::vector<double>>();
  m.output_std = s["output_std"].get<std::vector<double>>();
  for (std::size_t o = 0; o < m.outputs.size(); ++o) {
    const auto& fm = j["models"][o];
    odonata::fuzzy_rules_t f;
    f.output_name = m.outputs[o];
    f.num_inputs = fm["inputs"];
    f.num_rules = static_cast<int32_t>(fm["rules"].size());
    for (const auto& rule : fm["rules"]) {
      f.centres.push_back(rule["centre"].get<std::vector<double>>());
      f.sigmas.push_back(rule["sigma"].get<std::vector<double>>());
      f.output_widths.push_back(rule["output_width"].get<double>());
    }
    const auto& e = fm["entropy"];
    f.entropy_threshold = e["threshold"];
    f.max_rules = e["max_rules"];
    f.kappa = e["kappa"];
    f.sigma_init = e["sigma_init"];
    f.sigma_min = e["sigma_min"];
    f.sigma_max = e["sigma_max"];
    f.entropy_measure = e["measure"];
    f.prune_utility = e["prune_utility"];
    f.prune_min_age = e["prune_min_age"];
    f.clock = fm["clock"];
    f.pruned = fm["pruned"];
    for (const auto& rule : fm["rules"]) {
      f.utility_sums.push_back(rule["utility_sum"].get<double>());
      f.born.push_back(rule["born"].get<int64_t>());
    }
    const auto& a = fm["rates"];
    f.rate_centre = a["centre"];
    f.rate_sigma = a["sigma"];
    f.rate_output_width = a["output_width"];
    f.max_step = a["max_step"];
    const auto& c = fm["consequent"];
    f.consequent = c["kind"];
    f.nlms_rate = f.nlms_regulariser = f.rls_initial_covariance = 0;
    f.rls_forgetting = fm["forgetting"];
    if (f.consequent == "singleton") {
      f.nlms_rate = c["rate"];
      f.nlms_regulariser = c["regulariser"];
      f.num_coefficients = 1;
      for (double b : c["centres"]) f.coefficients.push_back({b});
      f.covariance_size = 0;
      f.covariances.assign(static_cast<std::size_t>(f.num_rules), {});
    } else {
      f.rls_initial_covariance = c["initial_covariance"];
      f.rls_forgetting = c["forgetting"];
      f.num_coefficients = f.num_inputs + 1;
      f.coefficients = c["coefficients"].get<std::vector<std::vector<double>>>();
      f.rls_forgetting = c["forgetting"];
      f.covariance_size = f.num_coefficients * f.num_coefficients;
      f.covariances = c["covariances"].get<std::vector<std::vector<double>>>();
    }
    m.models.push_back(std::move(f));
  }
  return m;
}

sysid::NarxModel DecodeSnapshot(const odonata::model_snapshot_t& m) {
  nlohmann::json j;
  j["format"] = "odonata-narx-fuzzy";
  j["version"] = 1;
  j["regressor"] = {{"output_lags", m.output_lags},
                    {"input_lags", m.input_lags},
                    {"delay", m.delay},
                    {"outputs", m.outputs},
                    {"inputs", m.inputs}};
  j["scaling"] = {{"regressor_mid", m.regressor_mid},
                  {"regressor_half", m.regressor_half},
                  {"output_mean", m.output_mean},
                  {"output_std", m.output_std}};
  nlohmann::json models = nlohmann::json::array();
  for (const auto& f : m.models) {
    nlohmann::json fm;
    fm["inputs"] = f.num_inputs;
    fm["entropy"] = {{"threshold", f.entropy_threshold},
                     {"max_rules", f.max_rules},
                     {"kappa", f.kappa},
                     {"sigma_init", f.sigma_init},
                     {"sigma_min", f.sigma_min},
                     {"sigma_max", f.sigma_max},
                     {"measure", f.entropy_measure},
                     {"prune_utility", f.prune_utility},
                     {"prune_min_age", f.prune_min_age}};
    fm["forgetting"] = f.rls_forgetting;
    fm["clock"] = f.clock;
    fm["pruned"] = f.pruned;
    fm["rates"] = {{"centre", f.rate_centre},
                   {"sigma", f.rate_sigma},
                   {"output_width", f.rate_output_width},
                   {"max_step", f.max_step}};
    nlohmann::json rules = nlohmann::json::array();
    for (int r = 0; r < f.num_rules; ++r) {
      const auto k = static_cast<std::size_t>(r);
      rules.push_back({{"centre", f.centres[k]},
                       {"sigma", f.sigmas[k]},
                       {"output_width", f.output_widths[k]},
                       {"utility_sum", f.utility_sums[k]},
                       {"born", f.born[k]}});
    }
    fm["rules"] = rules;
    nlohmann::json c;
    c["kind"] = f.consequent;
    if (f.consequent == "singleton") {
      c["rate"] = f.nlms_rate;
      c["regulariser"] = f.nlms_regulariser;
      std::vector<double> b;
      for (const auto& row : f.coefficients) {
        if (row.size() != 1)
          throw std::runtime_error("snapshot: singleton with several coefficients");
        b.push_back(row[0]);
      }
      c["centres"] = b;
    } else {
      c["initial_covariance"] = f.rls_initial_covariance;
      c["forgetting"] = f.rls_forgetting;
      c["coefficients"] = f.coefficients;
      c["covariances"] = f.covariances;
    }
    fm["consequent"] = c;
    models.push_back(fm);
  }
  j["models"] = models;
  return sysid::NarxModel::FromJson(j);
}

}  // namespace odonata::model_messages
