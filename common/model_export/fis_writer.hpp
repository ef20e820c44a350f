#pragma once
// MATLAB / Octave fuzzy-logic-toolkit `.fis` text of a raw Takagi–Sugeno model
// (docs/model_export.md §2): Sugeno, gaussmf inputs, linear or constant outputs, prod / wtaver.

#include <string>

#include "odonata/tsk_model.hpp"

namespace odonata::model_export {

/// Every number is written with 17 significant digits, so reading it back gives the same double.
std::string ToFis(const inference::TskModel& model);

}  // namespace odonata::model_export
