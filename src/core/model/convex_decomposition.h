// A mesh's approximate convex decomposition (HACD, from Bullet's extras): the parts a link's
// mesh collides as when the link asks for them. Private to flapsim_core.
#pragma once

#include "flapsim/creature_model.h"

namespace flapsim {

/// The convex parts of `mesh` (at least 1, at most `max_parts`, in 1..kMaxConvexHulls): its
/// triangles clustered by HACD (hierarchical approximate convex decomposition) until merging
/// two neighbouring clusters would leave a dent deeper than 1 % of the mesh's bounding-box
/// diagonal, then further while there are more than `max_parts`; each part is the vertices of
/// one cluster's triangles, sorted by index. The same mesh gives the same parts, bit for bit.
/// Throws std::runtime_error saying why there are none: over kMaxDecompositionTriangles
/// triangles, pieces too far apart to join into `max_parts`, or HACD's failure.
ConvexParts decomposeMesh(const MeshData& mesh, int max_parts);

}  // namespace flapsim
