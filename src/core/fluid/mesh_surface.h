// The air surface of a triangle mesh: its planar pieces (rectangles of two triangles, and
// triangles) cut into cells as a box's faces are, and whether a point lies inside it. Pure
// functions. Private to flapsim_core.
#pragma once

#include <vector>

#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/types.h"

namespace flapsim {

/// A planar piece of a mesh's surface, in the mesh's frame, with its cells.
struct MeshFace {
  Vec3 normal = Vec3::UnitZ();  // outward: from the triangles' winding
  Vec3 corners[4];              // a triangle repeats its last corner
  Vec3 edge = Vec3::UnitX();    // unit, along its longest edge
  std::vector<SurfaceCell> cells;
  /// A rectangle's grid (cell (i, j) is cells[i * nv + j], one step_u, step_v apart); 0 for a
  /// triangle.
  int nu = 0, nv = 0;
  Vec3 step_u = Vec3::Zero(), step_v = Vec3::Zero();
};

/// The faces of `mesh` for nu x nv subdivisions. Two triangles that share their longest edge,
/// lie in one plane and make a rectangle (a box's face as CAD programs and STL exporters write
/// it) are one face cut as a box face is: nu x nv cells, nu along the edge nearer the mesh
/// axis after the normal's (x after z, y after x, z after y), and one row across an edge at
/// most 0.25 of the other (a plate's rim). Any other triangle is a face of k x k equal cells
/// (its edges cut in k, each cell at its centroid), k = ceil(longest edge / h) within [1, 8],
/// h the largest extent of the mesh's bounds over max(nu, nv): cells about a box's of that
/// size. Every cell along its face's normal, with its share of the face's area.
std::vector<MeshFace> meshFaces(const MeshData& mesh, int nu, int nv);

/// The number of cells of meshFaces(mesh, nu, nv).
int meshCellCount(const MeshData& mesh, int nu, int nv);

/// Whether p (mesh frame) lies within `tolerance` of one of the mesh's triangles, or inside it
/// when it is closed (its winding number about p, from the triangles' solid angles, is 1).
bool insideMesh(const MeshData& mesh, const Vec3& p, double tolerance);

}  // namespace flapsim
