// The volume and centroid of a union of boxes (a link's displaced volume, for buoyancy).
// Pure functions. Private to flapsim_core.
#pragma once

#include <Eigen/Geometry>
#include <utility>
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

/// Boxes are grouped by their bounds sharing volume (a box in no group adds all of it). A group
/// whose boxes are axis-aligned with its first (any 90-degree turns) is measured exactly, in
/// O(k^2 log k) for k boxes (slabs between x faces, each a union of rectangles swept with a
/// segment tree). In any other group a box adds what of it lies outside the earlier boxes whose
/// bounds overlap its own, measured along 128 x 128 lines parallel to its x edge: exactly along
/// each line, by the midpoint rule across them, so the error is second order (3.5e-5 of the
/// overlap for a cube turned 45 degrees in another, see test_air), and the work is 128^2 line-box
/// tests per turnedOverlaps() pair. Finding the groups costs O(n log n + overlapping pairs).
BoxUnion unionOfBoxes(const std::vector<Box>& boxes);

/// Lines per edge of a box for the turned groups' measure.
constexpr int kUnionLines = 128;
/// The pairs of boxes whose bounds share volume within groups that are not axis-aligned: the
/// union's work is 128^2 line-box tests for each (a link's are bounded by kMaxTurnedOverlaps).
size_t turnedOverlaps(const std::vector<Box>& boxes);

/// The body-frame axis-aligned bounds of a box.
Eigen::AlignedBox3d boxBounds(const Box& box);

/// The pairs (i < j) of `bounds` that share volume: overlap by more than `margin` along every
/// axis. Sort and sweep along x: O(n log n + pairs whose x extents overlap).
std::vector<std::pair<size_t, size_t>> overlappingBounds(
    const std::vector<Eigen::AlignedBox3d>& bounds, double margin);

}  // namespace flapsim
