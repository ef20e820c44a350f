#include "fit/fit_report_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace odonata::fit {
namespace {

double Num(const nlohmann::json& v) { return v.is_null() ? NAN : v.get<double>(); }

void FormatHeader(std::ostream& out, const nlohmann::json& r) {
  out << "odonata-fit: " << r["target"].get<std::string>() << " from";
  for (const auto& name : r["regressors"]) out << ' ' << name.get<std::string>();
  out << "\n  " << r["rules"].get<int>() << " rules (" << r["consequent"].get<std::string>()
      << " consequents), entropy threshold H = " << r["entropy_threshold"].get<double>()
      << ", kappa " << r["kappa"].get<double>() << ", " << r["epochs"].get<int>() << " epochs, cap "
      << r["max_rules"].get<int>() << "\n";
  if (r.contains("refits")) {
    const auto& f = r["refits"];
    out << "  the online identifier replayed: " << f["samples_learned"].get<long>()
        << " samples learned, " << f["landed"].get<long>() << " refits landed ("
        << f["failed"].get<long>() << " failed, " << f["incumbents_kept"].get<long>()
        << " kept the last refit's model, " << f["steady_state_refused"].get<long>()
        << " steady-state models refused by their checks, " << f["linear_landed"].get<long>()
        << " landed the linear model, which won on the samples since they began)\n";
    for (const auto& s : f.value("seen_enough", nlohmann::json::array()))
      out << "  seen enough? " << s["output"].get<std::string>() << ": "
          << s["sentence"].get<std::string>() << "\n";
  }
}

// One line per candidate; `ahead` > 0 adds the K-step score's column. `final_rules`: the model's
// own count, which the chosen line names when training on every row changed it (the candidates
// are trained on the search's rows), so that a model's rule count is one number.
void FormatCandidates(std::ostream& out, const nlohmann::json& sel, int ahead, int final_rules) {
  char line[320];
  std::size_t k = 0;
  for (const auto& c : sel["candidates"]) {
    const bool chosen = k == sel["chosen_index"].get<std::size_t>();
    const bool best = k == sel["best_index"].get<std::size_t>();
    const bool linear = c.value("linear", false);
    const bool from_linear =
        !c["simulation"].empty() && c["simulation"].front().value("from_linear", false);
    char ahead_cell[32] = "";
    if (ahead > 0)
      std::snprintf(ahead_cell, sizeof ahead_cell, "  %13.4g",
                    Num(c.value("holdout_ahead_ndei", nlohmann::json())));
    const bool recounted = chosen && final_rules > 0 && c["rules"].get<int>() != final_rules;
    std::snprintf(
        line, sizeof line, "    %s %-10s %-8.4g %5.2g  %6d  %5d  %13.4g  %13.4g%s  %5.2g%s%s\n",
        chosen ? "*" : " ", linear ? "ARX" : c["consequent"].get<std::string>().c_str(),
        c["entropy_threshold"].get<double>(), c["kappa"].get<double>(), c["epochs"].get<int>(),
        c["rules"].get<int>(), Num(c["holdout_one_step_ndei"]), Num(c["holdout_free_run_ndei"]),
        ahead_cell, c.value("deviation_ridge", 0.0),
        c.value("restless", false)        ? "  (oscillates at rest)"
        : c.value("one_step_lost", false) ? "  (worse than ARX one step ahead)"
        : best && from_linear             ? "  (best; from ARX)"
        : best                            ? "  (best)"
        : from_linear                     ? "  (from ARX)"
                                          : "",
        recounted
            ? ("  (the model, trained on every row: " + std::to_string(final_rules) + " rules)")
                  .c_str()
            : "");
    out << line;
    ++k;
  }
}

// The linear model's two fits weighed, and the checks of fuzzy candidates against it.
void FormatLinearChecks(std::ostream& out, const nlohmann::json& sel) {
  char line[256];
  if (sel.contains("linear_fit_check")) {
    const auto& oc = sel["linear_fit_check"];
    std::snprintf(line, sizeof line,
                  "    the linear model's fits, %d folds, mean NDEI: output error %.4g, one "
                  "step %.4g: %s kept\n",
                  oc["folds"].get<int>(), Num(oc["output_error_ndei"]), Num(oc["one_step_ndei"]),
                  oc["output_error_kept"].get<bool>() ? "output error" : "one step");
    out << line;
  }
  if (!sel.contains("linear_check")) return;
  const nlohmann::json checks = sel.contains("linear_checks")
                                    ? sel["linear_checks"]
                                    : nlohmann::json::array({sel["linear_check"]});
  for (const auto& lc : checks) {
    const bool lost = lc["linear_chosen"].get<bool>();
    const bool last = &lc == &checks.back();
    std::snprintf(
        line, sizeof line,
        "    blocked cross-validation, %d folds, mean NDEI: fuzzy %.4g (%d rules), ARX %.4g, "
        "margin needed %.2g: %s\n",
        lc["folds"].get<int>(), Num(lc["fuzzy_ndei"]),
        lc.contains("candidate_index")
            ? sel["candidates"][lc["candidate_index"].get<std::size_t>()].value("rules", 0)
            : 0,
        Num(lc["linear_ndei"]), lc.value("margin", 0.0),
        !lost  ? "fuzzy kept"
        : last ? "ARX kept"
               : "lost, the next by hold-out is tried");
    out << line;
  }
}

void FormatSelection(std::ostream& out, const nlohmann::json& sel, int final_rules) {
  const std::string on = sel.value("scored_on", std::string("training hold-out"));
  out << "\n  model selection on " << sel["holdout_samples"].get<long>() << " samples of "
      << (on == "training hold-out" ? std::string("the training file's end") : on) << " ("
      << sel["criterion"].get<std::string>() << " NDEI; fewest rules within "
      << 100 * sel["relative_tolerance"].get<double>() << " % or "
      << sel["absolute_tolerance"].get<double>()
      << " of the best):\n      consequent  H        kappa  epochs  rules  one-step NDEI  "
         "free-run NDEI";
  // Scored K steps ahead, the score itself is a column too.
  const int ahead = sel["criterion"] == "k_step" ? sel["criterion_horizon"].get<int>() : 0;
  if (ahead > 0) {
    const std::string head = std::to_string(ahead) + "-step NDEI";
    out << std::string(15 - std::min<std::size_t>(head.size(), 13), ' ') << head;
  }
  out << "  ridge\n";
  if (sel.value("searched_rows", 0L) < sel.value("training_rows", 0L))
    out << "    (searched on " << sel["searched_rows"].get<long>() << " of the "
        << sel["training_rows"].get<long>()
        << " training rows, in blocks spread over the file; --search-rows)\n";
  FormatCandidates(out, sel, ahead, final_rules);
  FormatLinearChecks(out, sel);
}

// The validation's prediction intervals (prediction_intervals.hpp): coverage and mean width per
// mode, beside the FIT above.
void FormatIntervals(std::ostream& out, const nlohmann::json& b) {
  if (!b.contains("validate")) return;
  bool header = false;
  char line[256];
  for (const char* mode : {"one_step", "k_step", "free_run"}) {
    const auto& v = b["validate"];
    if (!v.contains(mode) || !v[mode].contains("interval")) continue;
    const auto& i = v[mode]["interval"];
    if (!header) {
      std::snprintf(line, sizeof line,
                    "\n  %.0f %% prediction intervals (split-conformal, %ld hold-out targets):\n",
                    100.0 * i["level"].get<double>(), i["calibration_rows"].get<long>());
      out << line;
      header = true;
    }
    if (i["mean_width"].is_null())
      std::snprintf(line, sizeof line, "  validate   %-10s covers %6.2f %%, unbounded\n", mode,
                    100.0 * i["coverage"].get<double>());
    else
      std::snprintf(line, sizeof line, "  validate   %-10s covers %6.2f %%, mean width %.4g\n",
                    mode, 100.0 * i["coverage"].get<double>(), i["mean_width"].get<double>());
    out << line;
  }
}

// One output's scores: the model's, then each baseline's, per data set and mode.
void FormatScores(std::ostream& out, const nlohmann::json& b) {
  const auto row = [&out](const char* data, const char* model, const nlohmann::json& block) {
    char line[256];
    for (const char* mode : {"one_step", "free_run", "k_step"}) {
      if (!block.contains(mode)) continue;
      const auto& a = block[mode];
      if (a.value("diverged", false))
        std::snprintf(line, sizeof line, "  %-10s %-10s %-11s %8s  %8s  %10s\n", data, mode, model,
                      "diverges", "–", "–");
      else
        std::snprintf(line, sizeof line, "  %-10s %-10s %-11s %8.2f  %8.2f  %10.4g\n", data, mode,
                      model, Num(a["fit"]), Num(a["vaf"]), Num(a["rmse"]));
      out << line;
    }
  };
  out << "\n  data       mode       model         FIT %     VAF %        RMSE\n";
  for (const char* data : {"train", "validate"}) {
    if (!b.contains(data)) continue;
    row(data, "fuzzy", b[data]);
    if (!b.contains("baselines")) continue;
    const auto& base = b["baselines"];
    if (base.contains("arx") && base["arx"].contains(data)) row(data, "ARX", base["arx"][data]);
    if (base.contains("arx_squared_inputs") && base["arx_squared_inputs"].contains(data))
      row(data, "ARX+u^2", base["arx_squared_inputs"][data]);
    if (base.contains("persistence") && base["persistence"].contains(data))
      row(data, "persistence", base["persistence"][data]);
    if (base.contains("readable") && base["readable"].contains(data))
      row(data, "readable", base["readable"][data]);
  }
  FormatIntervals(out, b);
}

// The readable form by default (the full one when there is none), the full one on request.
void FormatRules(std::ostream& out, const nlohmann::json& b, RulesShown rules_shown) {
  const bool readable = rules_shown == RulesShown::kReadable && b.contains("readable");
  if (rules_shown == RulesShown::kNone || (!readable && !b.contains("rule_text"))) return;
  if (readable) {
    const auto& rd = b["readable"];
    out << "\n  rules, readable form (" << rd["rules"].get<int>() << " of " << b["rules"].get<int>()
        << "; --full-rules for every rule):\n";
    for (const auto& s : rd["text"]) out << "    " << s.get<std::string>() << "\n";
    if (rd.contains("uncertainty") && !rd["uncertainty"].empty()) {
      // Weighted least squares on the training rows each rule fires on: the consequents' own
      // noise, not the simulation-error stages' shift nor a flight unlike the training one.
      out << "  local models, ± one standard error (training rows each rule fires on):\n";
      for (const auto& s : rd["uncertainty"]) out << "    " << s.get<std::string>() << "\n";
    }
    return;
  }
  out << "\n  rules:\n";
  int k = 1;
  for (const auto& s : b["rule_text"]) out << "  " << k++ << ". " << s.get<std::string>() << "\n";
}

void FormatFooter(std::ostream& out, const nlohmann::json& r) {
  if (r.contains("warnings")) {
    for (const auto& w : r["warnings"]) out << "\n  warning: " << w.get<std::string>();
    if (!r["warnings"].empty()) out << "\n";
  }
  if (r.contains("predictions_file"))
    out << "\n  predictions written to " << r["predictions_file"].get<std::string>() << "\n";
  if (r.contains("model_file"))
    out << "\n  model saved to " << r["model_file"].get<std::string>() << "\n";
  if (r.contains("plots") && !r["plots"].empty()) {
    out << "\n  pictures:";
    for (const auto& p : r["plots"]) out << " " << p.get<std::string>();
    out << "\n";
  }
}

}  // namespace

std::string FormatReport(const nlohmann::json& r, RulesShown rules_shown) {
  std::ostringstream out;
  FormatHeader(out, r);
  if (r.contains("verdict"))
    out << "  verdict: " << r["verdict"]["text"].get<std::string>() << "\n";
  if (r.contains("selection")) FormatSelection(out, r["selection"], r.value("rules", 0));
  // One table (and rule list) per output: the top level holds the first, per_output all.
  if (r.contains("per_output")) {
    for (const auto& [name, b] : r["per_output"].items()) {
      out << "\n  " << b["target"].get<std::string>() << ": " << b["rules"].get<int>()
          << " rules\n";
      FormatScores(out, b);
      FormatRules(out, b, rules_shown);
    }
  } else {
    FormatScores(out, r);
    FormatRules(out, r, rules_shown);
  }
  FormatFooter(out, r);
  return out.str();
}

}  // namespace odonata::fit
