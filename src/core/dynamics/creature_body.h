// The Bullet side of a creature: its multibody in a scene of its own, colliders, limits,
// joint servos and aero bodies, with the link kinematics, the ground check and the servo
// hook that the step uses. Private to flapsim_core.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <memory>
#include <vector>

#include "dynamics/bullet_scene.h"
#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "dynamics/joint_servo.h"
#include "dynamics/momentum.h"
#include "world/world_air.h"

namespace flapsim {

// Frames and velocities of every link's COM (index = model link), as Bullet computes them.
struct LinkFrames {
  // World-frame kinematics of link k's centre of mass; its rotation matrix in `rotation`.
  BodyKinematics kinematics(int k, Mat3* rotation = nullptr) const;

  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  std::vector<btVector3> omega, vel;  // in the link frames
};

struct CreatureBody {
  CreatureBody() = default;
  ~CreatureBody();
  CreatureBody(const CreatureBody&) = delete;
  CreatureBody& operator=(const CreatureBody&) = delete;

  // Refreshes `frames` from the multibody's state (Bullet's forwardKinematics).
  void updateKinematics();
  // The same frames, computed without touching the multibody or `frames`.
  LinkFrames currentFrames() const;

  // Whether a link could come within reach of the ground in this step (the link frames are
  // those of updateKinematics() at the start of the step). Creatures do not collide with
  // themselves, so without ground, or well above it, there is nothing to detect.
  bool mayTouch() const;

  // Called by Bullet once the velocities hold gravity, air and damping for this step:
  // solves every servo and the fluid's implicit part (added mass, linearised drag) together
  // and adds the velocity change they cause. The link frames are those of the start of the
  // step (positions have not moved).
  void applyServos();

  // The momentum bookkeeping of a step (see flapsim/momentum.h). beginStep() takes the
  // momentum at the start (frames of the start of the step); the air stage adds its
  // wrenches with addExternal(); endStep() moves each joint whose servo was saturated by the
  // trapezoid of its velocities (a constant torque), refreshes the frames after Bullet's
  // step and, unless the creature touches something (contact impulses are not known here)
  // or is anchored, gives the base the rigid correction that makes the momentum and the
  // centre of mass those of the external impulses.
  // `added_mass_density`: the density the plates' added mass is taken at (0: none).
  void beginStep(double added_mass_density);
  void addExternal(const Vec3& com, const Wrench& wrench);
  // This step's added mass of an aero body in a.added, world axes (`rotation`: its link's,
  // to world), about its COM, factored (empty without added mass); turned again only if
  // `rotation` or the density changed since it last was (the end of a step's momentum has
  // the next step's rotations).
  const SpatialFactor& turnedAddedMass(AeroBody& a, const Mat3& rotation) const;
  void endStep(const Vec3& gravity, double dt);
  // A corrected step ends with a known momentum, which the next beginStep() takes instead of
  // measuring it; call this after changing the multibody's state between steps.
  void forgetMomentum();

  std::unique_ptr<Scene> scene;  // declared first: destroyed last
  std::unique_ptr<btMultiBody> mb;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> limits;
  // Per model link: distance from its COM to the farthest corner of its boxes (0 if none).
  std::vector<double> reach;
  std::vector<double> max_effort;  // per model joint
  std::vector<double> damping;     // per model joint: URDF damping, capped for stability
  std::vector<double> stiffness;   // per model joint: <spring> stiffness, capped for stability
  // Joint servos (wing motors, velocity targets, feathering, Coulomb friction), indexed
  // by model link: the servo of the joint to that link's parent.
  const CreatureModel* model = nullptr;
  std::vector<double> servo_target;  // joint velocity wanted at the end of the step
  std::vector<ServoDemand> demands;
  std::vector<ServoLink> servo_links;
  JointServoSolver servo;
  ServoSolution solution;  // of the last step; impulses all zero if no servo acted
  std::vector<AeroBody> aero;
  bool fluid_active = false;  // this step's aero bodies carry implicit fluid matrices
  LinkFrames frames;          // of the last updateKinematics()
  double last_step = 1.0;     // s: the last (sub)step taken, for efforts from impulses

 private:
  void updateServoLinks();
  // Per link, the change of its spatial velocity [angular; linear at the root COM of the
  // step's start] since beginStep(), from the joints' (the motion subspaces of `tree`, else
  // of servo_links) into change_of_link_.
  void velocityChanges(const ServoTree& tree);
  // The momentum of the tree and of the fluid it carries, at the multibody's state (the
  // scene's TreeDynamics frames, which the next lean step's velocity update reuses).
  SystemMomentum measureMomentum();

  // This step's momentum balance: the start, and the external impulses so far (moments
  // about the root COM at the start of the step).
  SystemMomentum start_;
  SystemMomentum carried_;  // of the end of the last corrected step
  bool carried_valid_ = false;
  double carried_density_ = 0.0;
  Vec3 external_force_ = Vec3::Zero();
  Vec3 external_moment_ = Vec3::Zero();
  Vec6 drag_impulse_ = Vec6::Zero();  // of the implicit part of the drag
  double added_mass_density_ = 0.0;
  // Scratch, kept between steps: no allocation once warm.
  struct LinkMotion {  // of a link's COM, world frame
    Vec3 com = Vec3::Zero();
    Vec3 velocity = Vec3::Zero();
    Vec3 angular_velocity = Vec3::Zero();
  };
  std::vector<LinkMotion> motions_;           // measureMomentum()'s
  std::vector<double> start_joint_velocity_;  // per Bullet link
  Vec3 start_base_omega_ = Vec3::Zero();      // world frame
  Vec3 start_base_velocity_ = Vec3::Zero();   // of the base's COM
  ServoLoads loads_;
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> change_of_link_;
  // Per aero body in applyServos(): its drag matrix about the root COM, and Bullet's change
  // of its spatial velocity in this step.
  std::vector<Mat6, Eigen::aligned_allocator<Mat6>> drag_;
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> change_;
};

}  // namespace flapsim
