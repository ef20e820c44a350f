#pragma once
// odonata-fit's report as the text it prints without --json: the selection, the score table
// (the model beside ARX, ARX with squared inputs, persistence and its readable form) and rules.

#include <string>

#include <nlohmann/json.hpp>

namespace odonata::fit {

/// Which rules the text report lists: none, the readable form (docs/identifier.md §7.5), or every
/// rule of the full model.
enum class RulesShown { kNone, kReadable, kFull };

/// The readable table printed without --json.
std::string FormatReport(const nlohmann::json& report, RulesShown rules);

}  // namespace odonata::fit
