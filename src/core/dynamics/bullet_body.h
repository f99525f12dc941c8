// The Bullet side of a creature: its multibody in a scene of its own, its colliders and joint
// limits, and the link frames of the step, which every stage of a step reads (the frames of
// the step's start, until the momentum balance or Bullet's step writes those of its end).
// Private to flapsim_core.
#pragma once

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dynamics/bullet_scene.h"
#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/world.h"

namespace flapsim {

// Frames and velocities of every link's COM (index = model link): Bullet's link frames
// (rotation world -> link, COM position) and the COM's velocities in the link frame.
struct LinkFrames {
  // World-frame kinematics of link k's centre of mass; its rotation matrix in `rotation`.
  BodyKinematics kinematics(int k, Mat3* rotation = nullptr) const;
  // The same into `kin`, every field written (no temporary to copy).
  void kinematics(int k, BodyKinematics& kin) const;

  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  std::vector<btVector3> omega, vel;  // in the link frames
  // Where the momentum balance placed every link by `tree`'s frames (BulletBody::setFrame(),
  // then framesFromTree()): while that tree's frames are those of `tree_frames`, its
  // rotations are every link's rotation matrix, by kinematics()' arithmetic (Eigen's
  // toRotationMatrix of the same quaternions), which kinematics() then takes.
  const TreeDynamics* tree = nullptr;
  std::uint64_t tree_frames = 0;
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
  // Refreshes the frames from the multibody's state (Bullet's forwardKinematics).
  void updateKinematics();
  // The same frames, computed without touching the multibody or the frames.
  LinkFrames currentFrames() const;
  // After a step that the momentum balance did not correct: the frames where Bullet's step
  // (or a lean step, without writing the multibody) put the links.
  void framesAfterStep();
  // Link k's frame and velocities as the momentum balance placed them after its correction.
  void setFrame(int k, const btQuaternion& world_to_local, const btVector3& origin,
                const btVector3& omega, const btVector3& velocity);
  // After setFrame() of every link with the rotations of `tree`'s current frames.
  void framesFromTree(const TreeDynamics& tree) {
    frames_.tree = &tree;
    frames_.tree_frames = tree.framesCount();
  }
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
