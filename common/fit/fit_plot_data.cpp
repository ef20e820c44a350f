#include "fit/fit_plot_data.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "fuzzy/gaussian_rule_base.hpp"
#include "io/atomic_file.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/local_dynamics.hpp"

namespace odonata::fit {
namespace {

namespace fs = std::filesystem;

void WriteJson(const fs::path& path, const nlohmann::json& j) {
  io::WriteFileAtomically(path.string(), j.dump(1) + "\n");
}

// Sample, time, measured, one step, free run and the readable rules' firing, first output.
void WriteActivation(const fs::path& path, const sysid::NarxModel& model,
                     const sysid::ReadableModel* readable, const sysid::Series& run,
                     double sample_time_s) {
  const sysid::RegressorSpec& spec = model.spec();
  const sysid::Predictor predict = [&model](const Eigen::VectorXd& x) { return model.Predict(x); };
  const std::vector<Eigen::Index> rows = sysid::TargetRows(spec, run);
  const sysid::RegressionData data = sysid::BuildRegression(spec, run);
  const Eigen::MatrixXd one_step = sysid::PredictOneStep(spec, run, predict);
  const Eigen::MatrixXd free_run = sysid::SimulateFreeRun(spec, run, predict);
  std::ofstream out(path);
  out.precision(10);
  const int rules = readable ? readable->model.model(0).rules() : 0;
  out << "sample,t_s,measured,one_step,free_run";
  for (int j = 0; j < rules; ++j) out << ",rule_" << j + 1;
  out << "\n";
  fuzzy::Inference inference;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto t = static_cast<Eigen::Index>(r);
    out << rows[r] << ","
        << (sample_time_s > 0 ? static_cast<double>(rows[r]) * sample_time_s
                              : static_cast<double>(rows[r]))
        << "," << data.y(t, 0) << "," << one_step(t, 0) << "," << free_run(t, 0);
    if (rules > 0) {
      const sysid::NarxModel& rm = readable->model;
      const Eigen::VectorXd x = rm.scaling().ScaleRegressor(data.x.row(t).transpose());
      rm.model(0).rule_base().Evaluate(x, &inference);
      for (int j = 0; j < rules; ++j) out << "," << inference.normalized(j);
    }
    out << "\n";
  }
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

// A static map's output over its two most influential regressors (the others at their mean over
// the run): the regressors whose sweep across the data moves the output most.
void WriteSurface(const fs::path& path, const sysid::NarxModel& model, const sysid::Series& run) {
  const sysid::RegressionData data = sysid::BuildRegression(model.spec(), run);
  const Eigen::VectorXd mean = data.x.colwise().mean().transpose();
  const Eigen::VectorXd lo = data.x.colwise().minCoeff().transpose();
  const Eigen::VectorXd hi = data.x.colwise().maxCoeff().transpose();
  const Eigen::Index n = data.x.cols();
  std::vector<std::pair<double, Eigen::Index>> swing;
  for (Eigen::Index i = 0; i < n; ++i) {
    double least = 0, most = 0;
    for (int s = 0; s <= 20; ++s) {
      Eigen::VectorXd x = mean;
      x(i) = lo(i) + (hi(i) - lo(i)) * s / 20.0;
      const double y = model.Predict(x)(0);
      least = s == 0 ? y : std::min(least, y);
      most = s == 0 ? y : std::max(most, y);
    }
    swing.emplace_back(most - least, i);
  }
  std::sort(swing.begin(), swing.end(), [](const auto& a, const auto& b) { return a > b; });
  const auto names = model.spec().RegressorNames();
  std::ofstream out(path);
  out.precision(10);
  const Eigen::Index a = swing[0].second, b = n > 1 ? swing[1].second : swing[0].second;
  out << names[static_cast<std::size_t>(a)] << "," << names[static_cast<std::size_t>(b)] << ","
      << model.spec().outputs[0] << "\n";
  constexpr int kGrid = 41;
  for (int s = 0; s < kGrid; ++s) {
    for (int u = 0; u < kGrid; ++u) {
      Eigen::VectorXd x = mean;
      x(a) = lo(a) + (hi(a) - lo(a)) * s / (kGrid - 1.0);
      x(b) = lo(b) + (hi(b) - lo(b)) * u / (kGrid - 1.0);
      out << x(a) << "," << x(b) << "," << model.Predict(x)(0) << "\n";
    }
  }
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

// A dynamic model's steady-state gain over the two signals its rules are spread over most (one
// lag of each, the other regressors at their mean over the run): at each point the rules' local
// models blended by their firing there, as the model predicts, then analysed (local_dynamics).
void WriteGainSurface(const fs::path& path, const sysid::NarxModel& model,
                      const sysid::Series& run) {
  const fuzzy::FuzzyModel& fm = model.model(0);
  const fuzzy::GaussianRuleBase& base = fm.rule_base();
  const int rules = fm.rules();
  if (rules < 2) return;
  const sysid::RegressionData data = sysid::BuildRegression(model.spec(), run);
  const Eigen::VectorXd mean = data.x.colwise().mean().transpose();
  const Eigen::VectorXd lo = data.x.colwise().minCoeff().transpose();
  const Eigen::VectorXd hi = data.x.colwise().maxCoeff().transpose();
  const auto names = model.spec().RegressorNames();
  const auto signal = [&names](Eigen::Index i) {
    const std::string& n = names[static_cast<std::size_t>(i)];
    return n.substr(0, n.find('('));
  };
  std::vector<std::pair<double, Eigen::Index>> spread;
  for (Eigen::Index i = 0; i < data.x.cols(); ++i) {
    const auto c = base.centres_of_input(static_cast<int>(i));
    spread.emplace_back(c.maxCoeff() - c.minCoeff(), i);
  }
  std::sort(spread.begin(), spread.end(), [](const auto& x, const auto& y) { return x > y; });
  const Eigen::Index a = spread[0].second;
  Eigen::Index b = -1;
  for (const auto& [width, i] : spread)
    if (signal(i) != signal(a)) {
      b = i;
      break;
    }
  if (b < 0) return;  // one signal only: the gain schedule says it all
  std::vector<sysid::RawLinearModel> local;
  for (int j = 0; j < rules; ++j) local.push_back(sysid::RuleLinearModel(model, 0, j));
  std::ofstream out(path);
  out.precision(10);
  const sysid::LocalDynamics probe =
      sysid::AnalyseDynamics(model.spec(), 0, local[0], /*sample_time_s=*/0);
  out << names[static_cast<std::size_t>(a)] << "," << names[static_cast<std::size_t>(b)];
  for (const auto& [input, gain] : probe.dc_gain) out << ",gain from " << input;
  out << "\n";
  constexpr int kGrid = 31;
  fuzzy::Inference inference;
  for (int s = 0; s < kGrid; ++s) {
    for (int u = 0; u < kGrid; ++u) {
      Eigen::VectorXd x = mean;
      x(a) = lo(a) + (hi(a) - lo(a)) * s / (kGrid - 1.0);
      x(b) = lo(b) + (hi(b) - lo(b)) * u / (kGrid - 1.0);
      base.Evaluate(model.scaling().ScaleRegressor(x), &inference);
      sysid::RawLinearModel blend{0, Eigen::VectorXd::Zero(x.size())};
      for (int j = 0; j < rules; ++j) {
        blend.constant += inference.normalized(j) * local[static_cast<std::size_t>(j)].constant;
        blend.coefficients +=
            inference.normalized(j) * local[static_cast<std::size_t>(j)].coefficients;
      }
      const sysid::LocalDynamics d = sysid::AnalyseDynamics(model.spec(), 0, blend, 0);
      out << x(a) << "," << x(b);
      for (const auto& [input, gain] : d.dc_gain) out << "," << gain;
      out << "\n";
    }
  }
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

// A script of odonata's (fit_plots.py, fit_report.py): ODONATA_PYTHON_DIR, then the installed
// share/odonata/python, then the source tree.
std::string PythonScript(const std::string& name) {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("ODONATA_PYTHON_DIR")) dirs.emplace_back(env);
  dirs.emplace_back(ODONATA_INSTALLED_PYTHON_DIR);
  dirs.emplace_back(ODONATA_SOURCE_PYTHON_DIR);
  for (const auto& d : dirs) {
    const fs::path p = fs::path(d) / name;
    if (fs::exists(p)) return p.string();
  }
  throw std::runtime_error(name + " not found (looked in ODONATA_PYTHON_DIR, " +
                           std::string(ODONATA_INSTALLED_PYTHON_DIR) + " and " +
                           ODONATA_SOURCE_PYTHON_DIR + ")");
}

}  // namespace

void WritePlotData(const std::string& dir, const sysid::NarxModel& model,
                   const sysid::ReadableModel* readable, const sysid::Series& run,
                   double sample_time_s, const nlohmann::json& report) {
  const fs::path d(dir);
  std::error_code ec;
  fs::create_directories(d, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create (" + ec.message() + ")");
  WriteJson(d / "model.json", model.ToJson());
  if (readable) WriteJson(d / "readable_model.json", readable->model.ToJson());
  WriteJson(d / "report.json", report);
  WriteActivation(d / "activation.csv", model, readable, run, sample_time_s);
  if (model.spec().output_lags == 0)
    WriteSurface(d / "surface.csv", model, run);
  else if (model.model(0).consequent().kind() == fuzzy::ConsequentKind::kLinear)
    WriteGainSurface(d / "gain_surface.csv", model, run);
}

namespace {

// Runs `script DIR` by its own #! line (Debian's /usr/bin/python3, where python3-matplotlib
// installs), not whatever python3 comes first on the PATH; its stdout goes to stderr, since
// stdout may be odonata-fit's JSON.
void RunScript(const std::string& name, const std::string& dir) {
  const std::string script = PythonScript(name);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start python3 for " + name);
  if (pid == 0) {
    dup2(STDERR_FILENO, STDOUT_FILENO);
    execl(script.c_str(), script.c_str(), dir.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(
        name + " failed" +
        std::string(WIFEXITED(status) && WEXITSTATUS(status) == 127 ? " (it could not be run)"
                                                                    : "") +
        "; the data are in " + dir + " (" + script + " " + dir + " runs it again)");
}

}  // namespace

std::vector<std::string> DrawPlots(const std::string& dir) {
  RunScript("fit_plots.py", dir);
  std::vector<std::string> files;
  for (const char* name :
       {"membership.png", "activation.png", "surface.png", "gain_schedule.png", "gain_surface.png"})
    if (fs::exists(fs::path(dir) / name)) files.push_back((fs::path(dir) / name).string());
  return files;
}

std::string WriteReportPage(const std::string& dir) {
  RunScript("fit_report.py", dir);
  const fs::path page = fs::path(dir) / "index.html";
  if (!fs::exists(page)) throw std::runtime_error("fit_report.py wrote no " + page.string());
  return page.string();
}

}  // namespace odonata::fit
