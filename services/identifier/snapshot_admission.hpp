#pragma once
// Whether an identifier may resume from a snapshot heard on the bus: it must be a model of this
// identifier's signals and regressor, within this identifier's own bounds, with a usable
// scaling. Checked on the decoded message before any model is built from it, so a snapshot of
// another experiment (a roll identifier once resumed the previous pitch run's model) or one
// claiming absurd sizes starts the identifier fresh, with the reason, instead of being trusted.

#include <string>

#include "identifier_config/identifier_config.hpp"
#include "odonata/model_snapshot_t.hpp"

namespace odonata::identifier {

/// Empty when `snapshot` fits `config`, else every reason it does not.
std::string SnapshotMismatch(const odonata::model_snapshot_t& snapshot,
                             const IdentifierConfig& config);

}  // namespace odonata::identifier
