#include "sysid/selection/search_subsample.hpp"

#include <algorithm>

#include "sysid/selection/model_selection.hpp"

namespace odonata::sysid {

Series SubsampleForSearch(const Series& series, const SearchSubsample& budget) {
  const Eigen::Index n = series.samples();
  if (budget.rows <= 0 || n <= budget.rows) return series;
  const Eigen::Index blocks = std::max(1, budget.blocks);
  const Eigen::Index block = std::max<Eigen::Index>(1, budget.rows / blocks);
  Series out;
  for (Eigen::Index b = 0; b < blocks; ++b) {
    // Integer arithmetic, so the same record gives the same rows on every machine.
    const Eigen::Index begin = blocks == 1 ? n - block : b * (n - block) / (blocks - 1);
    const Series part = SliceSeries(series, begin, block);
    out = b == 0 ? part : ConcatSeries(out, part);
  }
  return out;
}

}  // namespace odonata::sysid
