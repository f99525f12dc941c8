// flapsim's own URDF elements, which urdfdom ignores: read from the same XML. Private to
// flapsim_core.
//   <wing joint="..." [feather_joint="..."]/>   a flapping joint (and the joint that pitches it)
//   <spring joint="..." stiffness="..." [reference="..."]/>   a joint's torsion spring
//   <motor joint="..." [stall_torque] [no_load_speed] [max_power]/>   a joint's DC motor
//   <aero link="..." drag_coefficient subdivisions="nu nv" enabled model span added_mass/>
//   <collision_mesh link="..." optimization="convex_hull|convex_decomposition"
//                   [max_convex_hulls="N"]/>   how the link's meshes collide
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"

namespace flapsim {

struct Annotations {
  std::vector<std::string> joint_order;  // the document order of <joint> elements
  std::vector<std::string> wings;
  std::vector<std::string> feathers;  // per wing, "" if none
  std::map<std::string, AeroSettings> aero;
  struct Spring {
    std::string joint;
    double stiffness = 0.0, reference = 0.0;
  };
  std::vector<Spring> springs;
  struct Motor {
    std::string joint;
    std::optional<double> stall_torque, no_load_speed;
    double max_power = 0.0;
  };
  std::vector<Motor> motors;
  /// A link's <collision_mesh>: whether its meshes collide as their convex decomposition (into
  /// at most max_convex_hulls parts) rather than as their convex hull.
  struct CollisionMesh {
    bool decompose = false;
    int max_convex_hulls = kDefaultMaxConvexHulls;
  };
  std::map<std::string, CollisionMesh> collision_meshes;  // by link name
};

/// Parses the XML, checks every link's and joint's numbers (model/urdf_numbers.h) and reads
/// the annotations. Throws ModelError naming `source` and the element at fault.
Annotations readAnnotations(const std::string& xml, const std::string& source);

/// Marks the wing joints and feather joints and sets the springs and motors of `model` (whose
/// joints are read) from `notes`. Throws ModelError naming `source` and the element at fault.
void applyJointAnnotations(const Annotations& notes, const std::string& source,
                           CreatureModel& model);

}  // namespace flapsim
