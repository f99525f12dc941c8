// The Bullet side of a creature: its multibody in a scene of its own, its colliders and joint
// limits, and the link frames of the step, which every stage of a step reads (the frames of
// the step's start, until the momentum balance or Bullet's step writes those of its end).
// Private to flapsim_core.
#pragma once

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <memory>
#include <string>
#include <vector>

#include "dynamics/bullet_scene.h"
#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/world.h"

namespace flapsim {

// Frames and velocities of every link's COM (index = model link): Bullet's link frames
// (rotation world -> link, COM position), the same rotations as matrices (link -> world), and
// the COM's velocities in the link frame. Written by BulletBody only, which sets each link's
// rotation and its matrix together: the two always agree.
class LinkFrames {
 public:
  // World-frame kinematics of link k's centre of mass; its rotation matrix in `rotation`.
  BodyKinematics kinematics(int k, Mat3* rotation = nullptr) const;
  // The same into `kin`, every field written (no temporary to copy).
  void kinematics(int k, BodyKinematics& kin) const;

  const btQuaternion& worldToLink(int k) const { return world_to_local_[k]; }
  const Mat3& rotation(int k) const { return rotation_[k]; }  // link -> world
  const btVector3& com(int k) const { return local_origin_[k]; }
  // The COM's velocities, in the link's frame.
  const btVector3& omega(int k) const { return omega_[k]; }
  const btVector3& velocity(int k) const { return vel_[k]; }

 private:
  friend class BulletBody;
  void resize(int links);
  // Every link's matrix from its rotation (after Bullet wrote all rotations at once): Eigen's
  // toRotationMatrix of its inverse.
  void updateRotations();

  btAlignedObjectArray<btQuaternion> world_to_local_;
  std::vector<Mat3, Eigen::aligned_allocator<Mat3>> rotation_;
  btAlignedObjectArray<btVector3> local_origin_;
  std::vector<btVector3> omega_, vel_;
};

// A movable joint's axis (world) and a point on it: a revolute joint's pivot, a prismatic
// joint's child link's COM.
struct JointAxis {
  Vec3 axis = Vec3::Zero(), point = Vec3::Zero();
};

// What a step may change in a multibody: enough to put it back bit for bit.
struct BodySnapshot {
  btVector3 position, velocity, omega;
  btQuaternion orientation;
  std::vector<double> q, qdot;

  void take(const btMultiBody& mb);
  void restore(btMultiBody& mb) const;
};

// The contact margin of a mesh's convex hulls (m): small against a wing's thickness, and
// enough for Bullet's convex contact (GJK/EPA) to keep resting contacts steady.
constexpr double kHullMargin = 1e-3;

// The colliders of `mesh` in its own frame, each a btConvexHullShape rounded by kHullMargin:
// its convex hull, or one per part of its convex decomposition (MeshShape::parts).
std::vector<std::unique_ptr<btConvexHullShape>> meshColliders(const MeshShape& mesh);

class BulletBody {
 public:
  // The body of creature `m` with its root link frame at `pose` moving with `twist`, in a
  // scene of its own. Keeps a pointer to `m`, which must outlive it.
  BulletBody(const CreatureModel& m, const Pose& pose, const Twist& twist,
             const WorldParams& params);
  ~BulletBody();
  BulletBody(const BulletBody&) = delete;
  BulletBody& operator=(const BulletBody&) = delete;

  btMultiBody& multiBody() { return *mb_; }
  const btMultiBody& multiBody() const { return *mb_; }
  ServoWorld& world() const { return scene_->world(); }
  // Whether the last collision detection left any contact manifold.
  bool hasContacts() const { return scene_->hasContacts(); }
  // Distance from link k's COM to the farthest corner of its boxes (0 if none).
  double reach(size_t k) const { return reach_[k]; }

  const LinkFrames& frames() const { return frames_; }
  // Movable joint `j`'s axis and a point on it, at the frames.
  JointAxis jointAxis(const JointModel& j) const;
  // Refreshes the frames from the multibody's state (Bullet's forwardKinematics).
  void updateKinematics();
  // The same frames, computed without touching the multibody or the frames.
  LinkFrames currentFrames() const;
  // After a step that the momentum balance did not correct: the frames where Bullet's step
  // (or a lean step, without writing the multibody) put the links.
  void framesAfterStep();
  // The frames as the momentum balance placed the links after its correction: every link's
  // rotation and its matrix those of `tree`'s frames (TreeDynamics::worldToLocal() and
  // rotations(), the same bits as updateKinematics() would give them), and link k's COM and
  // velocities.
  void setRotations(const TreeDynamics& tree);
  void setFrame(int k, const btVector3& origin, const btVector3& omega, const btVector3& velocity);
  // After the multibody's state was set from outside a step: the frames, the colliders and
  // the broadphase's pairs follow the new state, as for a body just built.
  void settle();

  // Whether a link could come within reach of the ground in this step (the frames are those
  // of the start of the step). Creatures do not collide with themselves, so without ground,
  // or well above it, there is nothing to detect.
  bool mayTouch() const;
  // Empty if every link has a finite pose and velocity and no point of it moves faster than
  // `max_speed`, else what is wrong, naming the link (the watchdog's check).
  std::string motionFault(double max_speed) const;

 private:
  void addColliders(double friction);
  void addCollider(const LinkModel& l, int k, double friction);
  btCollisionShape* linkShape(const LinkModel& l);
  btCollisionShape* roundLinkShape(const LinkModel& l);
  void addLimits();

  const CreatureModel& model_;
  std::unique_ptr<Scene> scene_;  // declared first: destroyed last
  std::unique_ptr<btMultiBody> mb_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders_;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> limits_;
  std::vector<double> reach_;  // per model link
  LinkFrames frames_;
};

}  // namespace flapsim
