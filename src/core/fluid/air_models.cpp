#include "flapsim/air_models.h"

namespace flapsim {

const std::vector<std::string>& airModelNames() {
  static const std::vector<std::string> names{"pressure", "quasi_steady"};
  return names;
}

std::string unknownAirModelMessage(const std::string& name) {
  std::string list;
  for (const std::string& n : airModelNames()) list += (list.empty() ? "" : ", ") + n;
  return "unknown air model '" + name + "' (" + list + ")";
}

}  // namespace flapsim
