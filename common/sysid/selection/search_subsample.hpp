#pragma once
// What the settings are chosen on when the record is long (docs/identifier.md §9, "Long
// records"): the search trains dozens of candidates for up to 50 epochs each, so on the whole of
// an hour-long log it would cost dozens of full fits. A fixed number of contiguous blocks spread
// evenly over the record sees every part of it (a flight's take-off, cruise and landing), keeps
// each block long enough for a free run, and bounds the search's cost whatever the record's
// length; the chosen setting is then trained on every row.

#include <Eigen/Core>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {

struct SearchSubsample {
  Eigen::Index rows = 20000;  ///< at most this many rows are searched; 0: the whole record
  int blocks = 4;             ///< contiguous blocks, evenly spread (the last ends the record)
};

/// `series` itself when it has at most `budget.rows` rows (or the budget is 0); otherwise
/// `budget.blocks` blocks of budget.rows / blocks rows, the first starting at row 0 and the last
/// ending at the record's end, joined with breaks (no regressor or free run crosses a seam), in
/// order — so the hold-out, the record's end, stays its end.
Series SubsampleForSearch(const Series& series, const SearchSubsample& budget);

}  // namespace odonata::sysid
