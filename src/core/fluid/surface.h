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
/// `rounds` (cylinders and spheres, body frame) add faceted faces, each flat facet a plain
/// cell list (nu = 0) with its outward normal and its share of the true area:
/// roundCellsAround(nu) strips around a cylinder's side times nv along it, plus two caps of
/// that many sectors; a sphere as roundCellsAround(nu) / 2 bands of equal height (equal area)
/// times roundCellsAround(nu) longitudes, each cell along its patch's mean normal (a sphere
/// cell's corners are its centre). `meshes` (body frame) add meshFaces(nu, nv): a rectangle
/// of two triangles cut as a box face, other triangles into cells of about a box cell's size.
/// Cells inside another shape are removed all ways (a closed mesh's inside by its winding
/// number). Their volumes (exact for each shape; a closed mesh's enclosed volume, an open
/// one's 0) are added to the boxes' union, the centroid volume-weighted: a round shape's or
/// mesh's overlap with another shape is counted twice.
AeroSurface buildSurface(const std::vector<Box>& boxes, int nu, int nv,
                         const std::optional<Vec3>& span = std::nullopt,
                         const std::vector<RoundShape>& rounds = {},
                         const std::vector<MeshShape>& meshes = {});

/// Facets around a cylinder or sphere for `nu` subdivisions: max(12, 3 nu).
int roundCellsAround(int nu);
/// The cells of a cylinder or sphere for nu, nv subdivisions (before hidden ones are removed).
int roundCellCount(const RoundShape& r, int nu, int nv);
/// The volume of a cylinder or sphere.
double roundVolume(const RoundShape& r);

/// The boxes of a link's added mass, in its COM frame: its boxes, and for each mesh whose
/// bounds in its own frame are plate-like (kPlateThickness) a box of those bounds (the plate
/// added mass of a box that size stands for the mesh's; other meshes add none). Its aero
/// surface takes its own boxes only.
std::vector<Box> comFrameBoxes(const LinkModel& link);
/// A link's cylinders and spheres, and its meshes, in its COM frame; and its cells per face
/// edge (its AeroSettings', else the world's), as its aero surface and added mass use them.
std::vector<RoundShape> comFrameRounds(const LinkModel& link);
std::vector<MeshShape> comFrameMeshes(const LinkModel& link);
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
