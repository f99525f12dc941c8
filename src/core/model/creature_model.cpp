#include "flapsim/creature_model.h"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <queue>
#include <set>

#include "flapsim/text_file.h"
#include "fluid/box_union.h"
#include "model/annotations.h"
#include "model/convex_decomposition.h"
#include "model/link_frames.h"
#include "model/mesh_loader.h"
#include "model/model_error.h"

namespace flapsim {

int CreatureModel::findLink(const std::string& link_name) const {
  for (size_t i = 0; i < links.size(); ++i) {
    if (links[i].name == link_name) return static_cast<int>(i);
  }
  return -1;
}

int CreatureModel::findJoint(const std::string& joint_name) const {
  for (size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].name == joint_name) return static_cast<int>(i);
  }
  return -1;
}

FrameOnLink CreatureModel::findFrame(const std::string& frame_name) const {
  const int k = findLink(frame_name);
  if (k >= 0) return FrameOnLink{k, links[k].urdf_frame};
  for (const LumpedLink& l : lumped) {
    if (l.name == frame_name) return FrameOnLink{l.link, links[l.link].urdf_frame * l.pose};
  }
  return FrameOnLink{};
}

Pose JointModel::childPose(double q, const Pose& parent) const {
  Quat r = parent.orientation * origin.orientation;
  Vec3 p = parent.apply(origin.position);
  if (type == JointType::kPrismatic) {
    p += r * (q * axis);
  } else if (movable()) {
    r = r * Quat(Eigen::AngleAxisd(q, axis));
  }
  return Pose{p, r};
}

Pose urdfJointPose(const CreatureModel& model, const JointModel& joint, double position) {
  Pose p = joint.childPose(position);
  if (joint.movable()) p.orientation.normalize();
  const LinkModel& parent = model.links.at(joint.parent_link);
  const LinkModel& child = model.links.at(joint.child_link);
  if (parent.rotated()) p = parent.urdf_frame.inverse() * p;
  return child.toUrdf(p);
}

double CreatureModel::totalMass() const {
  double m = 0.0;
  for (const auto& l : links) m += l.mass;
  return m;
}

namespace {

// Collects what urdfdom reports through console_bridge while it parses, so
// that its reasons (which link, which joint) reach our exception message.
class CapturingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) {
      if (!text_.empty()) text_ += "; ";
      text_ += text;
    }
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors_ = true;
  }
  const std::string& text() const { return text_; }
  bool errors() const { return errors_; }

 private:
  std::string text_;
  bool errors_ = false;
};

std::mutex& parserMutex() {
  static std::mutex m;
  return m;
}

Pose toPose(const urdf::Pose& p) {
  return Pose{Vec3(p.position.x, p.position.y, p.position.z),
              Quat(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized()};
}

bool finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

// The mesh of a <mesh> element, through `resolve`; a ModelError naming the link, the URI and
// why if it cannot be read.
MeshShape readMesh(const urdf::Mesh& mesh, const urdf::Pose& origin, const std::string& where,
                   const MeshResolver& resolve, const std::string& source) {
  MeshShape shape;
  shape.uri = mesh.filename;
  shape.scale = Vec3(mesh.scale.x, mesh.scale.y, mesh.scale.z);
  shape.origin = toPose(origin);
  const std::string what = where + ": mesh '" + mesh.filename + "'";
  if (!finite(shape.scale) || shape.scale.cwiseAbs().minCoeff() == 0.0 ||
      shape.scale.cwiseAbs().maxCoeff() > kMaxUrdfLength) {
    fail(source, what + ": scale must be non-zero and at most 1000 in magnitude");
  }
  try {
    shape.mesh = readMeshFile(resolve(mesh.filename), shape.scale);
  } catch (const std::exception& e) {
    fail(source, what + ": " + e.what());
  }
  for (const Vec3& v : shape.mesh->vertices) {
    if (v.cwiseAbs().maxCoeff() > kMaxUrdfLength) {
      fail(source, what + ": a vertex lies over 1000 m from the mesh's origin");
    }
  }
  return shape;
}

// The link's simulated shapes from its collision elements, or from its visual ones if it has
// no collision shape; meshes read through `resolve`.
void addShapes(const urdf::LinkConstSharedPtr& link, LinkModel& out, const MeshResolver& resolve,
               const std::string& source) {
  const std::string where = "link '" + link->name + "'";
  auto add = [&](const urdf::GeometrySharedPtr& g, const urdf::Pose& origin) {
    if (!g) return;
    switch (g->type) {
      case urdf::Geometry::BOX: {
        const auto& box = static_cast<const urdf::Box&>(*g);
        out.boxes.push_back(Box{Vec3(box.dim.x, box.dim.y, box.dim.z), toPose(origin)});
        return;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& c = static_cast<const urdf::Cylinder&>(*g);
        out.rounds.push_back(
            RoundShape{RoundShape::Kind::kCylinder, c.radius, c.length, toPose(origin)});
        return;
      }
      case urdf::Geometry::SPHERE: {
        const auto& sphere = static_cast<const urdf::Sphere&>(*g);
        out.rounds.push_back(
            RoundShape{RoundShape::Kind::kSphere, sphere.radius, 0.0, toPose(origin)});
        return;
      }
      case urdf::Geometry::MESH:
        out.meshes.push_back(
            readMesh(static_cast<const urdf::Mesh&>(*g), origin, where, resolve, source));
        return;
    }
  };
  for (const auto& c : link->collision_array) add(c->geometry, c->origin);
  if (!out.hasShapes()) {
    for (const auto& v : link->visual_array) add(v->geometry, v->origin);
    out.shapes_from_visuals = out.hasShapes();
  }
}

// urdfdom's model of the text, or a ModelError with what urdfdom reported.
urdf::ModelInterfaceSharedPtr parseUrdf(const std::string& urdf_xml, const std::string& source) {
  urdf::ModelInterfaceSharedPtr urdf;
  std::string urdf_messages;
  bool errors = false;
  {
    std::lock_guard<std::mutex> lock(parserMutex());
    CapturingHandler handler;
    console_bridge::useOutputHandler(&handler);
    try {
      urdf = urdf::parseURDF(urdf_xml);
    } catch (const std::exception& e) {
      handler.log(e.what(), console_bridge::CONSOLE_BRIDGE_LOG_ERROR, "", 0);
    }
    console_bridge::restorePreviousOutputHandler();
    urdf_messages = handler.text();
    errors = handler.errors();
  }
  if (!urdf) {
    fail(source, "invalid URDF" + (urdf_messages.empty() ? std::string() : ": " + urdf_messages));
  }
  // urdfdom drops an element it cannot read (a <sphere/> without a radius, a <mesh> scale of
  // NaN) and goes on: the creature would differ from its file.
  if (errors)
    fail(source, "the URDF parser dropped an element it could not read: " + urdf_messages);
  return urdf;
}

// A link's mass, COM (URDF frame), inertia and shapes; mass 0 without <inertial> or mass.
LinkModel readLink(const urdf::LinkConstSharedPtr& l, const MeshResolver& resolve,
                   const std::string& source) {
  LinkModel lm;
  lm.name = l->name;
  const std::string where = "link '" + l->name + "'";
  if (l->inertial && !(l->inertial->mass >= 0.0)) {
    fail(source, where + " has no positive mass (<inertial><mass value=.../>)");
  }
  if (l->inertial && l->inertial->mass > 0.0) {
    const auto& in = *l->inertial;
    lm.mass = in.mass;
    const Pose com = toPose(in.origin);
    lm.com = com.position;
    if (!finite(lm.com) || !std::isfinite(lm.mass)) fail(source, where + ": COM must be finite");
    setInertia(lm, com.orientation, {in.ixx, in.ixy, in.ixz, in.iyy, in.iyz, in.izz}, source);
  }
  const size_t shapes = std::max(l->collision_array.size(), l->visual_array.size());
  if (shapes > static_cast<size_t>(kMaxShapesPerLink)) {
    fail(source, where + " has " + std::to_string(shapes) + " shapes (<collision> or <visual>)" +
                     ", over the limit of " + std::to_string(kMaxShapesPerLink) + " per link");
  }
  addShapes(l, lm, resolve, source);
  for (const Box& b : lm.boxes) {
    if (!finite(b.size) || b.size.minCoeff() <= 0.0) {
      fail(source, where + ": box size must be positive");
    }
  }
  const size_t turned = turnedOverlaps(lm.boxes);
  if (turned > static_cast<size_t>(kMaxTurnedOverlaps)) {
    fail(source, where + ": " + std::to_string(turned) +
                     " pairs of its boxes overlap at angles other than 90 degrees, over the limit"
                     " of " +
                     std::to_string(kMaxTurnedOverlaps) + " per link");
  }
  for (const RoundShape& r : lm.rounds) {
    const bool cylinder = r.kind == RoundShape::Kind::kCylinder;
    if (!(r.radius > 0.0 && r.radius <= kMaxUrdfLength) ||
        (cylinder && !(r.length > 0.0 && r.length <= kMaxUrdfLength))) {
      fail(source, where + (cylinder ? ": cylinder radius and length" : ": sphere radius") +
                       " must be in (0, 1000] m");
    }
  }
  return lm;
}

// The convex decomposition of each of `link`'s meshes, as its <collision_mesh> asks;
// `triangles` counts those decomposed so far in the URDF (kMaxDecompositionTriangles bounds
// them all). A ModelError naming the link and the mesh if one cannot be decomposed.
void decomposeMeshes(const Annotations::CollisionMesh& settings, const std::string& source,
                     size_t& triangles, LinkModel& link) {
  const std::string where = "<collision_mesh link='" + link.name + "'>";
  if (link.meshes.empty()) fail(source, where + ": the link has no mesh to decompose");
  for (MeshShape& mesh : link.meshes) {
    const std::string what =
        "link '" + link.name + "': mesh '" + mesh.uri + "': no convex decomposition: ";
    triangles += mesh.mesh->triangles.size();
    if (triangles > static_cast<size_t>(kMaxDecompositionTriangles)) {
      fail(source, what + std::to_string(triangles) +
                       " triangles to decompose in the URDF up to this mesh, over the limit of " +
                       std::to_string(kMaxDecompositionTriangles) + " (simplify the mesh)");
    }
    try {
      mesh.parts =
          std::make_shared<const ConvexParts>(decomposeMesh(*mesh.mesh, settings.max_convex_hulls));
    } catch (const std::exception& e) {
      fail(source, what + e.what());
    }
  }
}

// The links parent-before-child (breadth first from the root), with their <aero> and
// <collision_mesh> settings; their indices by name into `index`.
void addLinks(const urdf::ModelInterface& urdf, Annotations& notes, const MeshResolver& resolve,
              const std::string& source, CreatureModel& model, std::map<std::string, int>& index) {
  std::queue<urdf::LinkConstSharedPtr> todo;
  todo.push(urdf.getRoot());
  size_t decomposed = 0;  // triangles
  while (!todo.empty()) {
    urdf::LinkConstSharedPtr l = todo.front();
    todo.pop();
    for (const auto& c : l->child_links) todo.push(c);
    if (l == urdf.getRoot() && l->name == "world") {
      model.fixed_base = true;
      index[l->name] = 0;
      LinkModel world;
      world.name = l->name;
      model.links.push_back(world);
      continue;
    }
    LinkModel lm = readLink(l, resolve, source);
    auto aero = notes.aero.find(l->name);
    if (aero != notes.aero.end()) {
      lm.aero = aero->second;
      notes.aero.erase(aero);
    }
    auto collision = notes.collision_meshes.find(l->name);
    if (collision != notes.collision_meshes.end()) {
      if (collision->second.decompose) {
        decomposeMeshes(collision->second, source, decomposed, lm);
      }
      notes.collision_meshes.erase(collision);
    }
    index[l->name] = static_cast<int>(model.links.size());
    model.links.push_back(lm);
  }
  if (!notes.aero.empty()) {
    fail(source, "<aero> names unknown link '" + notes.aero.begin()->first + "'");
  }
  if (!notes.collision_meshes.empty()) {
    fail(source,
         "<collision_mesh> names unknown link '" + notes.collision_meshes.begin()->first + "'");
  }
}

JointType jointType(int urdf_type, const std::string& where, const std::string& source) {
  switch (urdf_type) {
    case urdf::Joint::FIXED:
      return JointType::kFixed;
    case urdf::Joint::REVOLUTE:
      return JointType::kRevolute;
    case urdf::Joint::CONTINUOUS:
      return JointType::kContinuous;
    case urdf::Joint::PRISMATIC:
      return JointType::kPrismatic;
    default:
      fail(source, where + ": type not supported (use fixed, revolute, continuous or prismatic)");
  }
}

// A joint between two links of the tree (`index`: link indices by name).
JointModel readJoint(const urdf::Joint& j, const std::map<std::string, int>& index,
                     const std::string& source) {
  const std::string where = "joint '" + j.name + "'";
  JointModel jm;
  jm.name = j.name;
  jm.type = jointType(j.type, where, source);
  const auto parent = index.find(j.parent_link_name);
  const auto child = index.find(j.child_link_name);
  if (parent == index.end() || child == index.end() || child->second == 0) {
    fail(source, where + ": links '" + j.parent_link_name + "' -> '" + j.child_link_name +
                     "' are not a parent and child in the tree from the root link");
  }
  jm.parent_link = parent->second;
  jm.child_link = child->second;
  jm.origin = toPose(j.parent_to_joint_origin_transform);
  jm.axis = Vec3(j.axis.x, j.axis.y, j.axis.z);
  if (jm.movable()) {
    if (!finite(jm.axis) || jm.axis.norm() < 1e-9) fail(source, where + ": axis is zero");
    jm.axis.normalize();
  }
  if (j.limits) {
    jm.effort = j.limits->effort;
    jm.velocity = j.limits->velocity;
    if (jm.type == JointType::kRevolute || jm.type == JointType::kPrismatic) {
      jm.limited = true;
      jm.lower = j.limits->lower;
      jm.upper = j.limits->upper;
      if (!(jm.lower <= jm.upper)) fail(source, where + ": lower limit above upper limit");
    }
  }
  if (j.dynamics) {
    jm.damping = j.dynamics->damping;
    jm.friction = j.dynamics->friction;
    if (jm.damping < 0.0 || jm.friction < 0.0) {
      fail(source, where + ": damping and friction must be >= 0");
    }
  }
  return jm;
}

}  // namespace

CreatureModelPtr parseCreatureModel(const std::string& urdf_xml, const std::string& source,
                                    const MeshResolver& resolve_mesh) {
  Annotations notes = readAnnotations(urdf_xml, source);
  const urdf::ModelInterfaceSharedPtr urdf = parseUrdf(urdf_xml, source);
  auto model = std::make_shared<CreatureModel>();
  model->name = urdf->getName();
  model->source = source;
  std::map<std::string, int> link_index;
  std::set<std::string> aero_links;
  for (const auto& a : notes.aero) aero_links.insert(a.first);
  addLinks(*urdf, notes, resolve_mesh ? resolve_mesh : defaultMeshResolver(""), source, *model,
           link_index);
  // Joints in document order.
  for (const std::string& name : notes.joint_order) {
    urdf::JointConstSharedPtr j = urdf->getJoint(name);
    if (!j) continue;
    JointModel jm = readJoint(*j, link_index, source);
    model->links[jm.child_link].parent_joint = static_cast<int>(model->joints.size());
    model->joints.push_back(jm);
  }
  applyJointAnnotations(notes, source, *model);
  lumpMasslessLinks(*model, aero_links, source);
  expressInLinkFrames(*model);
  return model;
}

std::optional<Vec3> spanAxis(const CreatureModel& model, int link) {
  const LinkModel& l = model.links.at(static_cast<size_t>(link));
  if (l.parent_joint >= 0) {
    const JointModel& j = model.joints[l.parent_joint];
    if (j.wing) {
      // The joint's axis passes through the link frame's origin (URDF: joint frame = child
      // link frame), along j.axis: the span runs from that line out to the COM.
      const Vec3 out = l.com - l.com.dot(j.axis) * j.axis;
      if (out.norm() > 1e-9) return Vec3(out.normalized());
    }
    for (int w : model.wing_joints) {
      if (model.joints[w].feather_joint == l.parent_joint) return j.axis;
    }
  }
  return l.aero.span;
}

std::string readUrdfFile(const std::string& path) {
  try {
    return readTextFile(path, kMaxUrdfFileBytes);
  } catch (const InputError& e) {
    throw ModelError(e.what());
  }
}

double lowestBoxPoint(const CreatureModel& model, const std::vector<Pose>& link_poses) {
  double lowest = std::numeric_limits<double>::infinity();
  for (size_t l = 0; l < model.links.size() && l < link_poses.size(); ++l) {
    const Pose link = model.links[l].fromUrdf(link_poses[l]);
    for (const Box& box : model.links[l].boxes) {
      const Pose frame = link * box.origin;
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 half(corner & 1 ? 0.5 : -0.5, corner & 2 ? 0.5 : -0.5, corner & 4 ? 0.5 : -0.5);
        lowest = std::min(lowest, frame.apply(half.cwiseProduct(box.size)).z());
      }
    }
    for (const RoundShape& r : model.links[l].rounds) {
      const Pose frame = link * r.origin;
      double below = r.radius;  // a sphere; a cylinder: its lower rim or cap
      if (r.kind == RoundShape::Kind::kCylinder) {
        const Vec3 axis = frame.orientation * Vec3::UnitZ();
        below = 0.5 * r.length * std::abs(axis.z()) +
                r.radius * std::sqrt(std::max(0.0, 1.0 - axis.z() * axis.z()));
      }
      lowest = std::min(lowest, frame.position.z() - below);
    }
    for (const MeshShape& mesh : model.links[l].meshes) {
      const Pose frame = link * mesh.origin;
      for (const Vec3& v : mesh.mesh->vertices) lowest = std::min(lowest, frame.apply(v).z());
    }
  }
  return lowest;
}

std::vector<std::string> geometryNotes(const CreatureModel& model) {
  std::vector<std::string> lines;
  for (const LinkModel& link : model.links) {
    if (link.shapes_from_visuals) {
      lines.push_back("link '" + link.name +
                      "' has no <collision>: its <visual> shapes are simulated (contact and air)");
    }
    for (const MeshShape& mesh : link.meshes) {
      if (mesh.mesh->closed) continue;
      lines.push_back("link '" + link.name + "': mesh '" + mesh.uri + "' is not closed (" +
                      std::to_string(mesh.mesh->open_edges) +
                      " edges not run once each way): no volume (buoyancy), its air normals "
                      "from its triangles' winding");
    }
  }
  return lines;
}

std::string urdfDirectory(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

CreatureModelPtr loadCreatureModel(const std::string& path, const MeshResolver& resolve_mesh) {
  return parseCreatureModel(readUrdfFile(path), path,
                            resolve_mesh ? resolve_mesh : defaultMeshResolver(urdfDirectory(path)));
}

}  // namespace flapsim
