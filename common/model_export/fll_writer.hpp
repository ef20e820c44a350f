#pragma once
// fuzzylite `.fll` text of a raw Takagi–Sugeno model (docs/model_export.md §3): Gaussian input
// terms, Linear or Constant output terms, AlgebraicProduct conjunction, WeightedAverage.

#include <string>

#include "odonata/tsk_model.hpp"

namespace odonata::model_export {

/// Every number is written with 17 significant digits, so reading it back gives the same double.
std::string ToFll(const inference::TskModel& model);

}  // namespace odonata::model_export
