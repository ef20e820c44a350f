#pragma once
// `odonata-log topics`: every signal of a flight log, whatever its format (told by content), with
// what its format knows of it (a ULog's C type, a DataFlash unit, a Crazyflie struct code), its
// samples and the rate it was logged at.

#include <string>

/// Prints the log's signals whose names contain `match` (all when empty). Returns the exit code.
/// @throws std::runtime_error for a file that is no log this tool reads.
int Topics(const std::string& path, const std::string& match);
