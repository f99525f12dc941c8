// The aero surfaces of rigid bodies: each box face split into nu x nv cells (the paper's
// sub-surfaces), faces hidden inside the body removed, and a link's surface as the world
// uses it. Pure functions. Private to flapsim_core.
#pragma once

#include <optional>
#include <vector>

#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/types.h"

namespace flapsim {

/// Adds the 6 faces of a box (size, pose in the body frame), nu x nv cells each, to
/// `surface`, and its volume: the centroid becomes the volume-weighted mean of the boxes', so
/// this is right only for boxes that do not overlap (buildSurface handles overlaps). The span
/// of each face is its longer edge.
void appendBox(AeroSurface& surface, const Vec3& size, const Pose& origin, int nu, int nv);

/// The aero surface of a rigid body made of `boxes` (poses in the body/COM frame): the faces
/// of every box, nu x nv cells each, minus the cells whose centre lies inside another box or
/// on its surface (within 1e-6 of the largest box dimension): faces flush against or buried
/// in another box feel no air. Faces that keep all their cells keep the fast regular grid.
/// `span` (body frame, any length), projected onto each face that it is not nearly normal
/// to (at least 0.1 of it in the face plane), gives the faces' span; else the longer edge.
/// volume/centroid: unionOfBoxes. drag_coefficient and pitch_axis_point keep defaults.
AeroSurface buildSurface(const std::vector<Box>& boxes, int nu, int nv,
                         const std::optional<Vec3>& span = std::nullopt);

/// A link's boxes in its COM frame, and its cells per face edge (its AeroSettings', else the
/// world's), as its aero surface and its added mass use them.
std::vector<Box> comFrameBoxes(const LinkModel& link);
int subdivisionsU(const LinkModel& link, const AirParams& air);
int subdivisionsV(const LinkModel& link, const AirParams& air);

/// The aero surface of link `link` of `model`, as the world uses it: its boxes in its COM
/// frame, subdivisions and drag coefficient from its AeroSettings else from `air`, the span
/// of spanAxis(model, link), and the pitch axis through the link frame's origin when its
/// parent joint is a feather joint (else through the COM).
AeroSurface linkAeroSurface(const CreatureModel& model, int link, const AirParams& air);

/// Splits each of the 6 faces of a box (size, pose in the body frame) into an
/// nu x nv grid of cells.
std::vector<SurfaceCell> boxSurfaceCells(const Vec3& size, const Pose& origin, int nu, int nv);

}  // namespace flapsim
