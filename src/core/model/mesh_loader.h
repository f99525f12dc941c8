// Meshes of a URDF: their URIs resolved to files (as ROS does, without ROS), their files read
// through assimp, and their triangles checked (closed? which way out?). Private to flapsim_core.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"

namespace flapsim {

/// Largest mesh file read (bytes), and most triangles in one mesh: each triangle is at least
/// one air cell, and the cells of a link's other shapes are tested against every triangle.
constexpr std::size_t kMaxMeshFileBytes = 64u << 20;
constexpr std::size_t kMaxMeshTriangles = 200000;

/// The mesh of `vertices` and `triangles` (indices into them): triangles with a repeated
/// vertex or no area dropped; closed if every edge is run once each way, its triangles then
/// reversed if they enclose a negative volume; volume, centroid and bounds set.
MeshData makeMeshData(std::vector<Vec3> vertices, std::vector<std::array<int, 3>> triangles);

/// The triangles of mesh file `path` (any format assimp reads: STL ascii and binary, OBJ, DAE,
/// ...), every node's transform applied (a DAE's up axis ignored, as rviz does), vertices at
/// the same position welded, each scaled by `scale` (componentwise, no zero). Throws
/// std::runtime_error saying why it cannot (a missing or unreadable file, assimp's reason,
/// no triangles, over kMaxMeshFileBytes or kMaxMeshTriangles).
std::shared_ptr<const MeshData> readMeshFile(const std::string& path, const Vec3& scale);

/// The file of `uri` as defaultMeshResolver(base_dir) resolves it; throws std::runtime_error
/// saying why none.
std::string resolveMeshUri(const std::string& uri, const std::string& base_dir);

/// The directory of ROS package `name` on `ros_package_path` (':'-separated directories),
/// "" if none: the first directory, at most 8 levels down each, whose package.xml has
/// <name>name</name> (a directory with a package.xml is not searched further, nor one with a
/// CATKIN_IGNORE file, as rospack does).
std::string findRosPackage(const std::string& name, const std::string& ros_package_path);

}  // namespace flapsim
