#include "flapsim_ros/reconfigure_bounds.h"

#include <sstream>

namespace flapsim_ros {

std::vector<std::string> valuesAtBounds(const flapsim::FlapsimConfig& c,
                                        const flapsim::FlapsimConfig& before) {
  using Field = double flapsim::FlapsimConfig::*;
  static const std::vector<std::pair<const char*, Field>> kFields = {
      {"real_time_factor", &flapsim::FlapsimConfig::real_time_factor},
      {"publish_rate", &flapsim::FlapsimConfig::publish_rate},
      {"wind_x", &flapsim::FlapsimConfig::wind_x},
      {"wind_y", &flapsim::FlapsimConfig::wind_y},
      {"wind_z", &flapsim::FlapsimConfig::wind_z},
      {"density", &flapsim::FlapsimConfig::density},
      {"drag_coefficient", &flapsim::FlapsimConfig::drag_coefficient},
      {"gravity_x", &flapsim::FlapsimConfig::gravity_x},
      {"gravity_y", &flapsim::FlapsimConfig::gravity_y},
      {"gravity_z", &flapsim::FlapsimConfig::gravity_z}};
  const flapsim::FlapsimConfig& lo = flapsim::FlapsimConfig::__getMin__();
  const flapsim::FlapsimConfig& hi = flapsim::FlapsimConfig::__getMax__();
  std::vector<std::string> out;
  for (const auto& [name, field] : kFields) {
    const double v = c.*field;
    if (v == before.*field || (v != lo.*field && v != hi.*field)) continue;
    std::ostringstream text;
    text << name << " = " << v << ", the " << (v == hi.*field ? "top" : "bottom")
         << " of its range [" << lo.*field << ", " << hi.*field << "]";
    out.push_back(text.str());
  }
  return out;
}

}  // namespace flapsim_ros
