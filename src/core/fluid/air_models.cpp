#include "fluid/pressure.h"
#include "fluid/quasi_steady.h"

namespace flapsim {

AirModelPtr makeAirModel(const std::string& name) {
  if (name == "pressure") return std::make_shared<PressureAirModel>();
  if (name == "quasi_steady") return std::make_shared<QuasiSteadyAirModel>();
  return nullptr;
}

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
