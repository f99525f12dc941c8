#include "flapsim_ros/urdf_source.h"

#include <limits.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sstream>

#include "flapsim/creature_model.h"
#include "flapsim/types.h"

namespace flapsim_ros {

namespace {

// The canonical absolute path of `path`, or "" if it does not resolve.
std::string canonical(const std::string& path) {
  char resolved[PATH_MAX];
  if (path.empty() || !::realpath(path.c_str(), resolved)) return "";
  return resolved;
}

bool under(const std::string& file, const std::string& root) {
  if (root.empty()) return false;
  if (root == "/") return true;
  return file.size() > root.size() && file.compare(0, root.size(), root) == 0 &&
         file[root.size()] == '/';
}

}  // namespace

std::string refusedUrdfFileMessage(const std::string& path, const std::vector<std::string>& roots,
                                   const std::string& working_directory) {
  std::string text = "urdf_file '" + path +
                     "' refused: it must be a readable regular file of at most 16 MiB under an "
                     "allowed root (parameter ~urdf_roots:";
  for (size_t i = 0; i < roots.size(); ++i) text += (i ? ", " : " ") + roots[i];
  text += ")";
  if (!path.empty() && path[0] != '/') {
    text += "; a relative path starts at the node's working directory, " + working_directory +
            " (spawn_creature -file reads a file where it runs)";
  }
  return text;
}

std::string readSpawnUrdf(const std::string& path, const std::vector<std::string>& roots) {
  const std::string file = canonical(path);
  bool allowed = false;
  for (const std::string& root : roots) allowed = allowed || under(file, canonical(root));
  if (allowed) {
    try {
      return flapsim::readUrdfFile(file);
    } catch (const flapsim::ModelError&) {
    }
  }
  char cwd[PATH_MAX];
  throw flapsim::InputError(
      refusedUrdfFileMessage(path, roots, ::getcwd(cwd, sizeof cwd) ? cwd : "(unknown)"));
}

std::vector<std::string> defaultUrdfRoots(const char* ros_package_path,
                                          const std::string& working_directory) {
  std::vector<std::string> roots;
  if (ros_package_path) {
    std::istringstream in(ros_package_path);
    std::string dir;
    while (std::getline(in, dir, ':')) {
      if (!dir.empty()) roots.push_back(dir);
    }
  }
  if (!working_directory.empty()) roots.push_back(working_directory);
  return roots;
}

flapsim::MeshResolver spawnMeshResolver(
    const std::vector<std::string>& roots, const std::string& source,
    const std::function<std::string(const std::string&)>& package_path) {
  struct stat st {};
  const bool file = ::stat(source.c_str(), &st) == 0 && S_ISREG(st.st_mode);
  const flapsim::MeshResolver relative = flapsim::defaultMeshResolver(
      file ? flapsim::urdfDirectory(source) : "");  // a text has no directory
  return [roots, relative, package_path](const std::string& uri) {
    std::string path;
    const std::string scheme = "package://";
    if (uri.compare(0, scheme.size(), scheme) == 0) {
      const std::string rest = uri.substr(scheme.size());
      const size_t end = rest.find('/');
      const std::string package = rest.substr(0, end);
      const std::string found = package.empty() ? "" : package_path(package);
      if (found.empty()) throw flapsim::ModelError("unknown package '" + package + "'");
      path = end == std::string::npos ? found : found + rest.substr(end);
    } else {
      path = relative(uri);
    }
    const std::string file = canonical(path);
    for (const std::string& root : roots) {
      if (under(file, canonical(root))) return file;
    }
    std::string text =
        "refused: a mesh file must exist under an allowed root (parameter "
        "~urdf_roots:";
    for (size_t i = 0; i < roots.size(); ++i) text += (i ? ", " : " ") + roots[i];
    throw flapsim::ModelError(text + ")");
  };
}

}  // namespace flapsim_ros
