// The registry of built-in air-model names: the one list that validation, error messages
// and per-link model lookups derive from.
#pragma once

#include <string>
#include <vector>

namespace flapsim {

/// Names of the built-in air models, in a fixed order: {"pressure", "quasi_steady"}.
const std::vector<std::string>& airModelNames();

/// "unknown air model '<name>' (pressure, quasi_steady)", the list taken from airModelNames().
std::string unknownAirModelMessage(const std::string& name);

}  // namespace flapsim
