// The volume and centroid of a union of boxes (a link's displaced volume, for buoyancy).
// Pure functions. Private to flapsim_core.
#pragma once

#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/types.h"

namespace flapsim {

/// p in the frame of box `box` (centre at the origin, edges along the axes).
inline Vec3 inBox(const Box& box, const Vec3& p) {
  return box.origin.orientation.conjugate() * (p - box.origin.position);
}

/// The volume and centroid of a union of boxes (body frame), overlaps counted once.
struct BoxUnion {
  double volume = 0.0;
  Vec3 centroid = Vec3::Zero();
};

/// Exact when every box is axis-aligned with the first one (any 90-degree turns) or overlaps
/// no other. Otherwise a box whose bounds overlap an earlier box's adds what of it lies outside
/// the earlier boxes, measured along 128 x 128 lines parallel to its x edge: exactly along
/// each line, by the midpoint rule across them, so the error is second order (3.5e-5 of the
/// overlap for a cube turned 45 degrees in another, see test_air).
BoxUnion unionOfBoxes(const std::vector<Box>& boxes);

}  // namespace flapsim
