#include "model/mesh_loader.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace flapsim {

namespace {

// The edges of `triangles` not run exactly once each way.
int openEdges(const std::vector<std::array<int, 3>>& triangles) {
  std::map<std::pair<int, int>, int> runs;  // directed edge -> times run
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) ++runs[{t[k], t[(k + 1) % 3]}];
  }
  int open = 0;
  for (const auto& [edge, count] : runs) {
    const auto back = runs.find({edge.second, edge.first});
    const int reverse = back == runs.end() ? 0 : back->second;
    // Each undirected edge once: from its smaller end, or from the larger when never run back.
    if ((edge.first < edge.second || reverse == 0) && !(count == 1 && reverse == 1)) ++open;
  }
  return open;
}

}  // namespace

MeshData makeMeshData(std::vector<Vec3> vertices, std::vector<std::array<int, 3>> triangles) {
  MeshData m;
  m.vertices = std::move(vertices);
  if (!m.vertices.empty()) {
    m.lower = m.upper = m.vertices[0];
    for (const Vec3& v : m.vertices) {
      m.lower = m.lower.cwiseMin(v);
      m.upper = m.upper.cwiseMax(v);
    }
  }
  const double extent = (m.upper - m.lower).norm();
  for (const auto& t : triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    if ((b - a).cross(c - a).norm() <= 1e-15 * extent * extent) continue;
    m.triangles.push_back(t);
  }
  m.open_edges = openEdges(m.triangles);
  m.closed = !m.triangles.empty() && m.open_edges == 0;
  // Signed volume: tetrahedra from the origin, each at a quarter of its corners' sum.
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  for (const auto& t : m.triangles) {
    const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const double v = a.dot(b.cross(c)) / 6.0;
    volume += v;
    moment += v * (a + b + c) / 4.0;
  }
  if (m.closed && volume != 0.0) {
    m.centroid = moment / volume;
    if (volume < 0.0) {
      for (auto& t : m.triangles) std::swap(t[1], t[2]);
    }
    m.volume = std::abs(volume);
  } else {
    for (const Vec3& v : m.vertices) m.centroid += v;
    if (!m.vertices.empty()) m.centroid /= static_cast<double>(m.vertices.size());
  }
  return m;
}

std::shared_ptr<const MeshData> readMeshFile(const std::string& path, const Vec3& scale) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error("no such file '" + path + "'");
  if (!S_ISREG(st.st_mode)) throw std::runtime_error("'" + path + "' is not a regular file");
  if (static_cast<std::size_t>(st.st_size) > kMaxMeshFileBytes) {
    throw std::runtime_error("'" + path + "' has " + std::to_string(st.st_size) +
                             " bytes, over the limit of 64 MiB");
  }
  if (!std::ifstream(path).good()) throw std::runtime_error("cannot read '" + path + "'");
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices);
  if (!scene) {
    throw std::runtime_error("assimp cannot read '" + path + "': " + importer.GetErrorString());
  }
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::map<std::array<double, 3>, int> index;  // welds vertices at the same position
  for (unsigned k = 0; k < scene->mNumMeshes; ++k) {
    const aiMesh& mesh = *scene->mMeshes[k];
    std::vector<int> to(mesh.mNumVertices);
    for (unsigned i = 0; i < mesh.mNumVertices; ++i) {
      const aiVector3D& p = mesh.mVertices[i];
      const Vec3 v = Vec3(p.x, p.y, p.z).cwiseProduct(scale);
      const auto [at, added] = index.insert({{v.x(), v.y(), v.z()}, int(vertices.size())});
      if (added) vertices.push_back(v);
      to[i] = at->second;
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      triangles.push_back({to[face.mIndices[0]], to[face.mIndices[1]], to[face.mIndices[2]]});
    }
    if (triangles.size() > kMaxMeshTriangles) {
      throw std::runtime_error("'" + path + "' has over " + std::to_string(kMaxMeshTriangles) +
                               " triangles");
    }
  }
  for (const Vec3& v : vertices) {
    if (!v.allFinite()) throw std::runtime_error("'" + path + "' has a vertex that is not finite");
  }
  auto mesh = std::make_shared<MeshData>(makeMeshData(std::move(vertices), std::move(triangles)));
  if (mesh->triangles.empty()) throw std::runtime_error("'" + path + "' has no triangles");
  return mesh;
}

namespace {

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

// The <name> of package.xml `file`, "" if none.
std::string packageName(const std::string& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  static const std::regex name("<name>\\s*([^<\\s]+)\\s*</name>");
  std::smatch m;
  const std::string s = text.str();
  return std::regex_search(s, m, name) ? m[1].str() : "";
}

bool exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

// Depth-first below `dir` (at most `depth` levels) for package `name`.
std::string searchPackage(const std::string& dir, const std::string& name, int depth) {
  if (exists(dir + "/CATKIN_IGNORE")) return "";
  if (exists(dir + "/package.xml")) return packageName(dir + "/package.xml") == name ? dir : "";
  if (depth == 0) return "";
  std::vector<std::string> children;
  if (DIR* d = ::opendir(dir.c_str())) {
    while (const dirent* e = ::readdir(d)) {
      const std::string child = e->d_name;
      if (child.empty() || child[0] == '.') continue;
      struct stat st {};
      const std::string path = dir + "/" + child;
      if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) children.push_back(path);
    }
    ::closedir(d);
  }
  std::sort(children.begin(), children.end());
  for (const std::string& c : children) {
    const std::string found = searchPackage(c, name, depth - 1);
    if (!found.empty()) return found;
  }
  return "";
}

}  // namespace

std::string findRosPackage(const std::string& name, const std::string& ros_package_path) {
  std::istringstream in(ros_package_path);
  std::string dir;
  while (std::getline(in, dir, ':')) {
    if (dir.empty()) continue;
    // The usual layouts first: the directory itself, or a package in it.
    if (exists(dir + "/package.xml") && packageName(dir + "/package.xml") == name) return dir;
    const std::string found = searchPackage(dir, name, 8);
    if (!found.empty()) return found;
  }
  return "";
}

std::string resolveMeshUri(const std::string& uri, const std::string& base_dir) {
  if (startsWith(uri, "file://")) return uri.substr(7);
  if (startsWith(uri, "package://")) {
    const std::string rest = uri.substr(10);
    const size_t slash = rest.find('/');
    const std::string package = rest.substr(0, slash);
    const char* path = std::getenv("ROS_PACKAGE_PATH");
    const std::string dir = findRosPackage(package, path ? path : "");
    if (package.empty() || dir.empty()) {
      throw std::runtime_error("unknown package '" + package +
                               "' (no package.xml names it under ROS_PACKAGE_PATH '" +
                               (path ? path : "") + "')");
    }
    return slash == std::string::npos ? dir : dir + rest.substr(slash);
  }
  if (uri.find("://") != std::string::npos) {
    throw std::runtime_error("unsupported URI (use package://, file:// or a file path)");
  }
  if (startsWith(uri, "/")) return uri;
  if (base_dir.empty()) {
    throw std::runtime_error(
        "a relative path, and the URDF is not read from a file to be relative to (use "
        "package://, file:// or an absolute path)");
  }
  return base_dir + "/" + uri;
}

MeshResolver defaultMeshResolver(const std::string& base_dir) {
  return [base_dir](const std::string& uri) { return resolveMeshUri(uri, base_dir); };
}

}  // namespace flapsim
