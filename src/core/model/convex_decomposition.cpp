#include "model/convex_decomposition.h"

#include <HACD/hacdHACD.h>

#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace flapsim {

namespace {

// HACD scales the mesh so that its bounding-box diagonal is 2 kScale; its concavities are in
// those units.
constexpr double kScale = 1000.0;
// Deepest dent a part may fill: 1 % of the diagonal.
constexpr double kConcavity = 0.01 * 2.0 * kScale;

// HACD's cluster of each triangle (0 .. clusters - 1), clustering until the concavity exceeds
// `concavity` or `min_clusters` are left. HACD keeps global state: one at a time.
std::vector<long> clusterTriangles(const MeshData& mesh, size_t min_clusters, double concavity,
                                   size_t& clusters) {
  static std::mutex hacd_mutex;
  std::lock_guard<std::mutex> lock(hacd_mutex);
  // HACD normalises the points in place: a copy.
  std::vector<HACD::Vec3<HACD::Real>> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<HACD::Vec3<long>> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  HACD::HACD hacd;
  hacd.SetPoints(points.data());
  hacd.SetNPoints(points.size());
  hacd.SetTriangles(triangles.data());
  hacd.SetNTriangles(triangles.size());
  hacd.SetScaleFactor(kScale);
  hacd.SetCompacityWeight(0.1);  // Bullet's HACD demo's weights
  hacd.SetVolumeWeight(0.0);
  hacd.SetNClusters(min_clusters);
  hacd.SetConcavity(concavity);
  hacd.SetNVerticesPerCH(64);  // HACD's own hulls only: the parts take every vertex
  // A dent is measured from the clusters' vertices, their faces' centres and their
  // neighbours' points (the rays cast by extra distance points cost the square of the
  // triangles, and the faces' centres see the same dents).
  hacd.SetAddExtraDistPoints(false);
  hacd.SetAddNeighboursDistPoints(true);
  hacd.SetAddFacesPoints(true);
  if (!hacd.Compute()) throw std::runtime_error("HACD found no clusters");
  clusters = hacd.GetNClusters();
  const long* partition = hacd.GetPartition();
  if (clusters == 0 || !partition) throw std::runtime_error("HACD found no clusters");
  std::vector<long> cluster(partition, partition + mesh.triangles.size());
  for (long c : cluster) {
    if (c < 0 || static_cast<size_t>(c) >= clusters) {
      throw std::runtime_error("HACD left a triangle without a cluster");
    }
  }
  return cluster;
}

}  // namespace

ConvexParts decomposeMesh(const MeshData& mesh, int max_parts) {
  if (max_parts < 1 || max_parts > kMaxConvexHulls) {
    throw std::runtime_error("max_convex_hulls " + std::to_string(max_parts) + " is not in 1.." +
                             std::to_string(kMaxConvexHulls));
  }
  const size_t triangles = mesh.triangles.size();
  if (triangles > static_cast<size_t>(kMaxDecompositionTriangles)) {
    throw std::runtime_error(std::to_string(triangles) + " triangles, over the limit of " +
                             std::to_string(kMaxDecompositionTriangles) +
                             " for a convex decomposition (simplify the mesh)");
  }
  if (triangles == 0) throw std::runtime_error("no triangles to decompose");
  size_t clusters = 0;
  std::vector<long> cluster = clusterTriangles(mesh, 1, kConcavity, clusters);
  const size_t max = static_cast<size_t>(max_parts);
  if (clusters > max) {
    // Merged on in HACD's order, whatever the dents, down to max_parts.
    cluster = clusterTriangles(mesh, max, std::numeric_limits<double>::max(), clusters);
  }
  if (clusters > max) {
    throw std::runtime_error("HACD left " + std::to_string(clusters) +
                             " parts, more than max_convex_hulls " + std::to_string(max_parts) +
                             " (pieces of the mesh too far apart to join)");
  }
  // Each part's vertices by index, once each.
  std::vector<std::vector<bool>> used(clusters, std::vector<bool>(mesh.vertices.size(), false));
  for (size_t t = 0; t < triangles; ++t) {
    for (int v : mesh.triangles[t]) used[static_cast<size_t>(cluster[t])][v] = true;
  }
  ConvexParts parts(clusters);
  for (size_t c = 0; c < clusters; ++c) {
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
      if (used[c][v]) parts[c].push_back(mesh.vertices[v]);
    }
  }
  return parts;
}

}  // namespace flapsim
