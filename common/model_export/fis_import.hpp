#pragma once
// Rules an engineer wrote (or odonata exported), taken back in: a Sugeno .fis in raw units —
// the subset odonata-export writes, Gaussian inputs, linear or constant outputs — unfolded into
// the scaled network (docs/model_export.md §6), so the online identifier can start from it and
// refine it on the vehicle. The inverse of raw_tsk_model.hpp's folding.

#include <string>

#include "odonata/tsk_model.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::model_export {

/// A rule that leaves an input out ("don't care", an infinite width in the .fis reader) holds a
/// Gaussian this wide in scaled units: over the identifier's range [−1, 1] it changes a firing
/// by a factor between exp(−2·10⁻⁶) and 1.
inline constexpr double kDontCareWidth = 1000.0;

/// `tsk` as a model shaped like `empty` (its regressor, scaling, configuration; one output):
/// inputs must be the regressor in order, by the names odonata-export gives them (vz_k, u_km1,
/// …); constant outputs are linear ones with zero slopes when the configuration is linear.
/// Linear consequents start their learners from initial_covariance · I.
/// @throws std::invalid_argument naming what does not fit (`source` in front: the file).
sysid::NarxModel ModelFromTsk(const inference::TskModel& tsk, const sysid::NarxModel& empty,
                              const std::string& source);

/// Reads `path` (TskModel::FromFis, which names the line of a malformed file) and converts it.
/// @throws std::runtime_error or std::invalid_argument naming the file and the problem.
sysid::NarxModel LoadFis(const std::string& path, const sysid::NarxModel& empty);

}  // namespace odonata::model_export
