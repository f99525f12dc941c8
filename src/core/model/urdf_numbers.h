// The numbers of a URDF's links and joints, checked on its XML before urdfdom reads it
// (urdfdom drops a <collision> whose numbers it cannot read, and passes on NaN, inf and
// 1e300): each known attribute must hold its count of finite numbers within its range.
// Private to flapsim_core.
#pragma once

#include <tinyxml2.h>

#include <string>

namespace flapsim {

/// Efforts, speeds, damping, friction, stiffness: any sane value fits within this.
constexpr double kHugeUrdfValue = 1e9;

/// Throws ModelError naming `source`, the link or joint and the attribute at fault.
void checkAllNumbers(const tinyxml2::XMLElement* robot, const std::string& source);

}  // namespace flapsim
