// The controller weights file: a flap-unit network's settings and weights as YAML, as
// evolve writes it and ann_controller reads it. Apart from the GA (flapsim/evolve.h), so
// that a controller needs only this and flapsim/ann.h. ROS-free.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "flapsim/ann.h"
#include "flapsim/text_file.h"

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
/// Largest weights file read (bytes): 1 MiB (a network of kMaxHidden neurons is 30 kB).
constexpr std::size_t kMaxControllerFileBytes = 1u << 20;
/// Reads (readTextFile, at most kMaxControllerFileBytes) and parses a weights file.
ControllerSpec loadControllerYaml(const std::string& path);

}  // namespace flapsim
