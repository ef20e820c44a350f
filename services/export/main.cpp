// odonata-export: writes a saved odonata model as MATLAB/Octave .fis and fuzzylite .fll files in
// raw units (docs/model_export.md), for tools and flight code that know nothing of odonata.

#include <cmath>
#include <filesystem>
#include <iostream>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/parse_command_line.hpp"
#include "io/atomic_file.hpp"
#include "model_export/exact_number.hpp"
#include "model_export/fis_writer.hpp"
#include "model_export/fll_writer.hpp"
#include "model_export/octave_local_models.hpp"
#include "model_export/raw_tsk_model.hpp"

namespace {

// "roll.fis" → "roll.p_kp1.fis" when a model has several outputs: one file per output.
std::string PerOutput(const std::string& path, const std::string& output, bool several) {
  if (!several) return path;
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + "." + output + p.extension().string())).string();
}

}  // namespace

int main(int argc, char** argv) {
  std::string model_path, fis, fll, only, name, local_models;
  double sample_time_s = 0;
  CLI::App app{
      "Writes a saved odonata model (odonata-fit --save-model, odonata-identifier --save-model) "
      "as a Sugeno .fis (MATLAB, Octave's fuzzy-logic-toolkit, fuzzylite) and a fuzzylite .fll, "
      "in raw units: the model's scaling is folded into the centres, widths and coefficients. "
      "Inputs are the regressor in the order printed. A model with several outputs gives one "
      "file per output (NAME.OUTPUT.fis)."};
  app.add_option("model", model_path, "saved model (JSON)")->required()->check(CLI::ExistingFile);
  app.add_option("--fis", fis, ".fis file to write");
  app.add_option("--fll", fll, ".fll file to write");
  app.add_option("--output", only, "export only this output signal (default: every one)");
  app.add_option("--name", name, "system name inside the files (default: the model file's stem)");
  app.add_option("--local-models", local_models,
                 "Octave script to write: each rule's linear local model as a discrete "
                 "state-space model, loaded as octave-control ss objects (local_models(k).sys)");
  app.add_option("--sample-time", sample_time_s,
                 "with --local-models: the sample time in seconds (default: the one the model "
                 "was saved with, odonata-fit's when it knew the rate; else 1, time in samples)")
      ->check(CLI::PositiveNumber);
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  if (fis.empty() && fll.empty() && local_models.empty()) {
    std::cerr << "odonata-export: nothing to write; give --fis FILE, --fll FILE and/or "
                 "--local-models FILE.m\n";
    return 2;
  }
  try {
    const auto model = odonata::sysid::NarxModel::Load(model_path);
    if (name.empty()) name = std::filesystem::path(model_path).stem().string();
    const auto& outputs = model.spec().outputs;
    bool found = only.empty();
    std::vector<int> chosen;
    for (int o = 0; o < model.outputs(); ++o) {
      const std::string& out_name = outputs[static_cast<std::size_t>(o)];
      if (!only.empty() && only != out_name) continue;
      found = true;
      chosen.push_back(o);
      const bool several = only.empty() && model.outputs() > 1;
      const auto tsk = odonata::model_export::ToRawTsk(model, o, name);
      std::string order;
      for (const auto& in : tsk.input_names) order += (order.empty() ? "" : ", ") + in;
      if (!fis.empty()) {
        const auto path = PerOutput(fis, out_name, several);
        // The sample time, for whoever simulates the rules as a discrete model: a comment
        // before [System], which MATLAB, Octave and fuzzylite skip.
        const double ts = sample_time_s > 0
                              ? sample_time_s
                              : odonata::sysid::NarxModel::SavedSampleTime(model_path);
        const std::string ts_line =
            ts > 0 ? "% Sample time Ts = " + odonata::model_export::ExactNumber(ts) + " s\n"
                   : "% Sample time unknown: time in samples\n";
        odonata::io::WriteFileAtomically(path, ts_line + odonata::model_export::ToFis(tsk));
        std::cout << "wrote " << path << "\n";
      }
      if (!fll.empty()) {
        const auto path = PerOutput(fll, out_name, several);
        odonata::io::WriteFileAtomically(path, odonata::model_export::ToFll(tsk));
        std::cout << "wrote " << path << "\n";
      }
      std::cout << "  " << tsk.output_name << " = f(" << order << "): " << tsk.rules.size()
                << (tsk.linear ? " linear" : " constant") << " rules\n";
      const auto& lim = model.limits();
      if (lim.any() && (std::isfinite(lim.lower(o)) || std::isfinite(lim.upper(o))))
        // The file formats have no such hold: a client evaluating them must clamp.
        std::cout << "  note: the model holds " << out_name << " to [" << lim.lower(o) << ", "
                  << lim.upper(o) << "], a saturation found in its training data "
                  << "(docs/identifier.md §7.2); the exported rules do not: clamp their output\n";
    }
    if (!found) {
      std::cerr << "odonata-export: the model has no output '" << only << "'\n";
      return 1;
    }
    if (!local_models.empty()) {
      if (!(sample_time_s > 0))
        sample_time_s = odonata::sysid::NarxModel::SavedSampleTime(model_path);
      if (!(sample_time_s > 0))
        std::cerr << "odonata-export: warning: " << model_path
                  << " holds no sample time: the local models' Ts is 1 (time in samples); give "
                     "--sample-time SECONDS\n";
      const auto covariance = odonata::sysid::NarxModel::SavedLocalCovariance(model_path);
      odonata::io::WriteFileAtomically(
          local_models, odonata::model_export::OctaveLocalModels(model, chosen, sample_time_s,
                                                                 model_path, covariance));
      std::cout << "wrote " << local_models << " (each rule's state-space model, octave-control"
                << (covariance.is_null() ? "; no parameter covariance in the model file"
                                         : ", with its parameter covariance")
                << ")\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "odonata-export: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
