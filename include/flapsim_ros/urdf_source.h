// Where a spawn request may read a URDF file from. No ROS: tested without a master.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"

namespace flapsim_ros {

/// The text of URDF file `path` for a spawn request: after resolving symbolic links and
/// "..", it must lie under one of `roots` and be a regular file of at most 16 MiB
/// (flapsim::readUrdfFile). Any refusal throws flapsim::InputError with the same text
/// (refusedUrdfFileMessage), whatever the reason, so that a reply does not tell which files
/// exist on the host.
std::string readSpawnUrdf(const std::string& path, const std::vector<std::string>& roots);

/// The one text of a refused `urdf_file`: it names the roots, and for a relative path the
/// working directory it starts at.
std::string refusedUrdfFileMessage(const std::string& path, const std::vector<std::string>& roots,
                                   const std::string& working_directory);

/// The default roots: the directories on `ros_package_path` (':'-separated; may be null)
/// and `working_directory`.
std::vector<std::string> defaultUrdfRoots(const char* ros_package_path,
                                          const std::string& working_directory);

/// How the node finds a spawned URDF's meshes: "package://pkg/..." in `package_path(pkg)`
/// (the node: ros::package::getPath; "" for an unknown package), anything else as
/// flapsim::defaultMeshResolver resolves it, relative paths against the directory of `source`
/// when it names a regular file (a urdf_file). The file must lie under one of `roots` (after
/// resolving symbolic links and ".."), as a urdf_file must: else it is refused with one text
/// whatever the reason, so that a reply does not tell which files exist on the host.
flapsim::MeshResolver spawnMeshResolver(
    const std::vector<std::string>& roots, const std::string& source,
    const std::function<std::string(const std::string&)>& package_path);

}  // namespace flapsim_ros
