// The controller weights file: a flap-unit network's settings and weights as YAML, as
// evolve writes it and ann_controller reads it. Apart from the GA (flapsim/evolve.h), so
// that a controller needs only this and flapsim/ann.h. ROS-free.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "flapsim/ann.h"

namespace flapsim {

/// A controller as stored in a weights YAML file.
struct ControllerSpec {
  FlapControllerParams params;
  std::vector<double> weights;
};

/// YAML text of a controller (key `flap_unit_controller`), preceded by the
/// `header` lines as comments and followed by `metadata` (key `evolution`).
std::string controllerToYaml(const ControllerSpec& spec, const std::string& header = "",
                             const std::map<std::string, std::string>& metadata = {});
/// Parses controllerToYaml() output; checks the weight count. Throws
/// std::runtime_error naming `source` and the bad key.
ControllerSpec controllerFromYaml(const std::string& text, const std::string& source = "<string>");
ControllerSpec loadControllerYaml(const std::string& path);
/// Throws std::runtime_error if the file cannot be written.
void writeTextFile(const std::string& path, const std::string& text);
/// Throws InputError if the file cannot be read.
std::string readTextFile(const std::string& path);

}  // namespace flapsim
