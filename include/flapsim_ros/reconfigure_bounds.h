// dynamic_reconfigure clamps a value outside its range in cfg/Flapsim.cfg to the bound before
// the node sees it: the node names the values that landed on a bound, so that a clamp (density
// 1e9 -> 1e5) is logged. A pure function of the configs: tested without a master.
#pragma once

#include <string>
#include <vector>

#include "flapsim/FlapsimConfig.h"

namespace flapsim_ros {

/// The doubles of `config` that changed from `before` to a bound of their range, one text
/// each ("density = 100000, the top of its range [0, 100000]").
std::vector<std::string> valuesAtBounds(const flapsim::FlapsimConfig& config,
                                        const flapsim::FlapsimConfig& before);

}  // namespace flapsim_ros
