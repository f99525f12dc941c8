// The hover controller's gains file: HoverControllerParams as one flat YAML map, each key a
// field's name (hoverParamFields). The hover_controller node loads it as its private
// parameters (`<rosparam command="load" file="..."/>` in hover.launch), flight_check --hover
// --gains reads it, evolve --preset hover writes it and reads it with --init. ROS-free.
#pragma once

#include <cstddef>
#include <map>
#include <string>

#include "flapsim/hover_controller.h"

namespace flapsim {

/// YAML text of `params` (every field but `altitude`, the flight's setpoint, which the node
/// and flight_check take from their own --altitude / ~altitude), preceded by the `header`
/// lines as comments and followed by `metadata` as comments (`# key: value`), so that
/// rosparam loads only the gains.
std::string hoverGainsToYaml(const HoverControllerParams& params, const std::string& header = "",
                             const std::map<std::string, std::string>& metadata = {});

/// The params of a gains file's text: the defaults (HoverControllerParams()) with each key
/// given. Throws InputError naming `source` and the culprit: not a YAML map, an unknown key, a
/// value that is not a finite number, invalid params (validateHoverControllerParams).
HoverControllerParams hoverGainsFromYaml(const std::string& text,
                                         const std::string& source = "<string>");

/// Largest gains file read (bytes).
constexpr std::size_t kMaxHoverGainsFileBytes = 64u << 10;

/// Reads (readTextFile, at most kMaxHoverGainsFileBytes) and parses a gains file.
HoverControllerParams loadHoverGainsYaml(const std::string& path);

}  // namespace flapsim
