// The Bullet side of a creature: its multibody in a scene of its own, colliders, limits,
// joint servos and aero bodies, with the link kinematics, the ground check and the servo
// hook that the step uses. Private to flapsim_core.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <memory>
#include <vector>

#include "bullet_scene.h"
#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/joint_servo.h"
#include "world_air.h"

namespace flapsim {

// Frames and velocities of every link's COM (index = model link), as Bullet computes them.
struct LinkFrames {
  // World-frame kinematics of link k's centre of mass.
  BodyKinematics kinematics(int k) const;

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
  // solves every servo together and adds the velocity change it causes. The link frames
  // are those of updateKinematics() at the start of the step (positions have not moved).
  void applyServos();

  std::unique_ptr<Scene> scene;  // declared first: destroyed last
  std::unique_ptr<btMultiBody> mb;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> limits;
  // Per model link: distance from its COM to the farthest corner of its boxes (0 if none).
  std::vector<double> reach;
  std::vector<double> max_effort;  // per model joint
  std::vector<double> damping;     // per model joint: URDF damping, capped for stability
  // Joint servos (wing motors, velocity targets, feathering, Coulomb friction), indexed
  // by model link: the servo of the joint to that link's parent.
  const CreatureModel* model = nullptr;
  std::vector<double> servo_target;  // joint velocity wanted at the end of the step
  std::vector<ServoDemand> demands;
  std::vector<ServoLink> servo_links;
  JointServoSolver servo;
  ServoSolution solution;  // of the last step; impulses all zero if no servo acted
  std::vector<AeroBody> aero;
  LinkFrames frames;  // of the last updateKinematics()

 private:
  void updateServoLinks();
};

}  // namespace flapsim
