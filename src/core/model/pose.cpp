#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "flapsim/types.h"

namespace flapsim {

Pose poseFromXyzRpy(const Vec3& xyz, const Vec3& rpy) {
  Quat q = Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
           Eigen::AngleAxisd(rpy.x(), Vec3::UnitX());
  return Pose{xyz, q.normalized()};
}

double bankAngle(const Quat& orientation) {
  return std::asin(std::clamp((orientation * Vec3::UnitY()).z(), -1.0, 1.0));
}

}  // namespace flapsim
