// CreatureModel: an immutable description of a creature, read from URDF.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/types.h"

namespace flapsim {

/// Per-link air settings from `<aero link=... drag_coefficient=... subdivisions="nu nv"
/// enabled=... model="pressure|quasi_steady" span="x|y|z"/>`. Unset values fall back to the
/// world's AirParams.
struct AeroSettings {
  bool enabled = true;
  std::optional<double> drag_coefficient;
  std::string model;       // air model name; empty: world default
  int subdivisions_u = 0;  // 0: world default
  int subdivisions_v = 0;
  std::optional<Vec3> span;        // span="x|y|z": that unit axis of the link frame (see spanAxis)
  std::optional<bool> added_mass;  // added_mass="true|false"; unset: the world's setting
};

/// A box of the link's geometry, in the link frame.
struct Box {
  Vec3 size = Vec3::Zero();
  Pose origin;
};

/// A cylinder (URDF: its axis is z of `origin`, centred there) or a sphere of the link's
/// geometry, in the link frame: a collider and a faceted air surface (roundSurfaceCells).
struct RoundShape {
  enum class Kind { kCylinder, kSphere };
  Kind kind = Kind::kSphere;
  double radius = 0.0;
  double length = 0.0;  // cylinder only
  Pose origin;
};

/// The triangles of a mesh file (assimp: STL, OBJ, DAE, ...), its vertices scaled by the
/// <mesh scale> and in the mesh's frame; identical vertices welded. Immutable once loaded.
struct MeshData {
  std::vector<Vec3> vertices;
  /// Vertex indices, counter-clockwise seen from outside: as the file winds them, all reversed
  /// if it is closed and they enclose a negative volume (an inside-out file, a mirror scale).
  std::vector<std::array<int, 3>> triangles;
  /// Whether it is a closed, consistently wound surface: each edge is run once each way.
  bool closed = false;
  int open_edges = 0;            // edges not run exactly once each way (0 when closed)
  double volume = 0.0;           // the enclosed volume if closed, else 0
  Vec3 centroid = Vec3::Zero();  // of that volume (of the vertices if not closed)
  Vec3 lower = Vec3::Zero(), upper = Vec3::Zero();  // bounds of the vertices
};

/// The convex parts of a mesh's convex decomposition, each as the points (vertices of the
/// mesh, in its frame) whose convex hull is the part.
using ConvexParts = std::vector<std::vector<Vec3>>;

/// A <mesh> of the link's geometry, in the link frame: a collider (its convex hull, or the
/// parts of its convex decomposition) and an air surface (its triangles, see meshFaces).
struct MeshShape {
  std::string uri;            // the <mesh filename>, for messages
  Vec3 scale = Vec3::Ones();  // the <mesh scale> (already applied to mesh->vertices)
  Pose origin;
  std::shared_ptr<const MeshData> mesh;
  /// The parts it collides as when its link asks for a convex decomposition
  /// (`<collision_mesh link="..." optimization="convex_decomposition"/>`); null: it collides as
  /// its convex hull.
  std::shared_ptr<const ConvexParts> parts;
};

/// A link's frame is its URDF frame unless the URDF's inertia tensor has products of inertia
/// (ixy, ixz, iyz) or a rotated <inertial><origin rpy>: then its axes are the principal axes
/// of inertia (same origin), and every link-frame quantity below (COM, shapes, the joints'
/// origins and axis, the aero span) is in that frame. `urdf_frame` is the URDF link frame in
/// the link frame: users see URDF frames (CreatureState, StateRequest, spawn poses, tf).
struct LinkModel {
  std::string name;
  double mass = 0.0;
  Vec3 com = Vec3::Zero();         // centre of mass in the link frame
  Vec3 inertia = Vec3::Zero();     // principal moments about the COM, link axes
  Pose urdf_frame;                 // the URDF link frame in the link frame (a rotation)
  std::vector<Box> boxes;          // collision boxes (visual ones if it has no collision)
  std::vector<RoundShape> rounds;  // collision cylinders and spheres (likewise)
  std::vector<MeshShape> meshes;   // collision meshes (likewise)
  /// Whether its shapes come from its <visual> elements (it has no <collision>).
  bool shapes_from_visuals = false;
  AeroSettings aero;
  int parent_joint = -1;  // index into CreatureModel::joints, -1 for the root

  bool hasShapes() const { return !boxes.empty() || !rounds.empty() || !meshes.empty(); }
  /// Whether the link frame differs from the URDF frame (urdf_frame is not exactly identity).
  bool rotated() const { return urdf_frame.orientation.coeffs() != Quat::Identity().coeffs(); }
  /// The URDF frame's pose given the link frame's `pose` (in any frame), and back; `pose`
  /// itself, bit for bit, unless rotated().
  Pose toUrdf(const Pose& pose) const { return rotated() ? pose * urdf_frame : pose; }
  Pose fromUrdf(const Pose& pose) const { return rotated() ? pose * urdf_frame.inverse() : pose; }
  /// The centre of mass in the URDF link frame.
  Vec3 urdfCom() const { return rotated() ? Vec3(urdf_frame.inverse().apply(com)) : com; }
};

/// A link without mass on a fixed joint (a CAD model's base_link, a sensor's frame), lumped
/// into the link it is fixed to, as Gazebo's URDF import does: its shapes are that link's,
/// its child joints hang from it. It remains a frame (tf, StateRequest::link, ...).
struct LumpedLink {
  std::string name;
  std::string joint;  // the fixed joint it hung on ("" for a massless root)
  int link = -1;      // the link it is lumped into (index into CreatureModel::links)
  Pose pose;          // its URDF frame in that link's URDF frame
};

/// A named frame of a creature as a link of the model and the frame's pose in that link's
/// frame (LinkModel::urdf_frame for a link's own URDF frame); link -1 if none has the name.
struct FrameOnLink {
  int link = -1;
  Pose pose;
};

enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic };

/// A joint's motor, from `<motor joint="..." stall_torque="..." no_load_speed="..."
/// max_power="..."/>`: a DC motor behind a current-limited driver (src/core/dynamics/motor.h).
/// Driving, its torque is at most stall_torque (1 - |v| / no_load_speed) and at most
/// max_power / |v| at joint velocity v; braking, at most stall_torque. A joint without one
/// has the flat limit |torque| <= <limit effort> at any speed.
struct MotorSpec {
  double stall_torque = 0.0;   // N m (N if prismatic), > 0; default: <limit effort>
  double no_load_speed = 0.0;  // rad/s (m/s); default: <limit velocity>; 0: no speed line
  double max_power = 0.0;      // W; 0: no power limit
};

struct JointModel {
  std::string name;
  JointType type = JointType::kFixed;
  int parent_link = -1;
  int child_link = -1;
  Pose origin;                // child link frame in the parent link frame at zero position
  Vec3 axis = Vec3::UnitX();  // unit axis in the child frame
  bool limited = false;
  double lower = 0.0, upper = 0.0;
  double effort = 0.0;    // torque/force limit (0: unlimited in URDF terms)
  double velocity = 0.0;  // speed limit (0: none)
  double damping = 0.0;
  double friction = 0.0;
  /// <spring joint="..." stiffness="..." reference="..."/>: a torsion spring (N m/rad, or N/m
  /// if prismatic) pulling the joint towards `reference`. On a driven joint (a wing's stroke
  /// hinge) it acts in parallel with the motor, as the thorax of an insect and the hinge
  /// springs of motor-driven flapping robots do: it stores the wing's kinetic energy at each
  /// stroke reversal and gives it back.
  double stiffness = 0.0;
  double reference = 0.0;
  std::optional<MotorSpec> motor;  // <motor joint="..."/>; none: the flat effort limit
  bool wing = false;               // marked by <wing joint="..."/>
  int feather_joint = -1;          // <wing joint="..." feather_joint="..."/>: pitches this wing

  bool movable() const { return type != JointType::kFixed; }
  /// The forward kinematics of the joint, the one every chain of links is walked with (link
  /// poses for tf, urdfJointPose, unitSensing): the child link's frame with the joint at `q`
  /// (rad, or m if prismatic; ignored if fixed) given the parent link's frame `parent` (in any
  /// frame; the default, the parent link frame itself, gives the child's frame in it):
  /// `parent`, then `origin`, then the joint's rotation about or translation along `axis` by
  /// `q`, composed in that order. The orientation is the plain product, not normalised again
  /// (within a few ulp of unit): a caller walking a chain normalises where it keeps a result.
  Pose childPose(double q, const Pose& parent = Pose()) const;
};

/// Links are stored parent-before-child, the root first; joints in URDF order. The root is
/// the URDF's root link, or, if that has no mass, the first link with mass fixed to it.
struct CreatureModel {
  std::string name;    // the URDF robot name
  std::string source;  // file name or "<string>", for messages
  std::vector<LinkModel> links;
  std::vector<JointModel> joints;
  std::vector<int> wing_joints;  // indices into joints, in URDF order
  /// The root link is named "world" (the gazebo_ros convention): the creature is anchored
  /// at its spawn pose. The "world" link needs no inertia.
  bool fixed_base = false;
  std::vector<LumpedLink> lumped;  // massless links on fixed joints, in URDF order

  int findLink(const std::string& link_name) const;
  int findJoint(const std::string& joint_name) const;
  /// A link's or a lumped link's frame by name (see FrameOnLink).
  FrameOnLink findFrame(const std::string& frame_name) const;
  double totalMass() const;
};

using CreatureModelPtr = std::shared_ptr<const CreatureModel>;

/// The file path of a <mesh filename> URI; throws (ModelError or any std::exception) saying
/// why it has none, e.g. an unknown package.
using MeshResolver = std::function<std::string(const std::string& uri)>;

/// Resolves URIs as ROS does, without ROS: "file:///abs/path" and "/abs/path" as they are; a
/// relative path against `base_dir` (the URDF file's directory; refused if empty);
/// "package://pkg/rel/path" in the first directory found under ROS_PACKAGE_PATH (searched to
/// depth 8, as rospack does) whose package.xml has <name>pkg</name>. Anything else is refused.
MeshResolver defaultMeshResolver(const std::string& base_dir = "");

/// The directory of a URDF file's path, against which its relative mesh paths resolve: "." for
/// a bare file name, "/" for a file at the root.
std::string urdfDirectory(const std::string& path);

/// Parses URDF text; `source` names it in errors. Meshes are read through `resolve_mesh`
/// (empty: defaultMeshResolver("")). Throws ModelError naming the source and the link or
/// joint at fault; a mesh that cannot be resolved or read names its link, its URI and why.
CreatureModelPtr parseCreatureModel(const std::string& urdf_xml,
                                    const std::string& source = "<string>",
                                    const MeshResolver& resolve_mesh = {});

/// The child link's URDF frame in the parent link's URDF frame with joint `joint` at
/// `position` (what tf publishes).
Pose urdfJointPose(const CreatureModel& model, const JointModel& joint, double position);

/// One line per link whose visual shapes are simulated for want of a <collision>, and per mesh
/// that is not closed (no volume, normals from its winding), naming the link and the mesh;
/// empty if neither. (The simulator node says these at a spawn.)
std::vector<std::string> geometryNotes(const CreatureModel& model);

/// Largest URDF file read (bytes): 16 MiB, far beyond any creature's description.
constexpr std::size_t kMaxUrdfFileBytes = 16u << 20;

/// Largest magnitudes a URDF may give (beyond them a model is refused, naming the value): a
/// length or coordinate (m), a mass (kg), a moment of inertia (kg m^2).
constexpr double kMaxUrdfLength = 1e3;
/// Most <collision> (or <visual>) elements of a link: its air surface and union volume are
/// built in at most O(k^2 log k) of them (box_union, surface), bounded by this.
constexpr int kMaxShapesPerLink = 256;
/// Most pairs of a link's boxes that overlap at angles other than multiples of 90 degrees: the
/// union volume measures each along 128 x 128 lines (box_union), so this bounds that work.
constexpr int kMaxTurnedOverlaps = 256;
/// Most convex parts a mesh's decomposition may ask for (`max_convex_hulls`), and its default
/// (SDFormat's): each part is a convex collider of the link, tested at every contact step.
constexpr int kMaxConvexHulls = 64;
constexpr int kDefaultMaxConvexHulls = 16;
/// Most triangles of the meshes a URDF asks to decompose, all together: the decomposition's
/// time grows faster than a mesh's triangles (4.8 s of CPU for 4992, doc/urdf.md), and it
/// runs at every spawn of the URDF.
constexpr int kMaxDecompositionTriangles = 5000;
constexpr double kMaxUrdfMass = 1e6;
constexpr double kMaxUrdfInertia = 1e6;

/// The text of a URDF file: a regular file (not a directory, FIFO or device) of at most
/// kMaxUrdfFileBytes. Throws ModelError naming the file and what is wrong.
std::string readUrdfFile(const std::string& path);

/// The lowest z of the model's boxes (their corners), meshes (their vertices), cylinders and
/// spheres with its links at `link_poses` (URDF link frames in the world, as CreatureState's);
/// +infinity for a model without shapes.
double lowestBoxPoint(const CreatureModel& model, const std::vector<Pose>& link_poses);

/// Reads (readUrdfFile) and parses a URDF file, its meshes through `resolve_mesh` (empty:
/// defaultMeshResolver of the file's directory). Throws ModelError naming the file.
CreatureModelPtr loadCreatureModel(const std::string& path, const MeshResolver& resolve_mesh = {});

/// The spanwise axis (unit, sign arbitrary) of link `link` in its COM frame, whose axes are the
/// link frame's: for a link hanging from a wing joint, the direction from the joint's axis out
/// to the link's COM (none if the COM is on the axis); for a link hanging from a wing's
/// feather joint, that joint's axis; else the link's `<aero span="x|y|z">`; else none (the
/// quasi-steady model then takes each face's longer edge).
std::optional<Vec3> spanAxis(const CreatureModel& model, int link);

}  // namespace flapsim
