// Where a spawn request may read a URDF file from. No ROS: tested without a master.
#pragma once

#include <string>
#include <vector>

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

}  // namespace flapsim_ros
