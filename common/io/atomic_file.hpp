#pragma once
// Files that are either whole or absent, and names that cannot leave their directory: for the
// model files an operator (or anyone on the control channel) asks a service to write.

#include <string>

namespace odonata::io {

/// Writes `content` to `path` through a fresh temporary file in the same directory (created
/// exclusively, so never through a planted symlink), flushed to disk, then renamed over `path`: a
/// crash mid-write leaves the old file, never a truncated one, and a symlink at `path` is replaced,
/// not followed.
/// @throws std::runtime_error naming the file on any failure (the temporary file is removed).
void WriteFileAtomically(const std::string& path, const std::string& content);

/// `name` inside `directory`, for a name received from outside: a plain file name of letters,
/// digits, '.', '_' and '-', not starting with '.', at most 128 characters.
/// @throws std::invalid_argument saying why the name is refused (a path, "..", a hidden name, an
///   empty directory).
std::string ConfinedPath(const std::string& directory, const std::string& name);

}  // namespace odonata::io
