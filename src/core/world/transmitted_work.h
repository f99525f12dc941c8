// The motors' work from what their joints transmit (MotorWorkMeter::kTransmitted, the
// default; world/power.h takes it). Private to flapsim_core.
//
// A servo's impulse times its joint's move carries, besides the motor's work, the error of
// the explicit step's velocity products, which the servo takes out again to hold its rate:
// first order in the step (1 % of the flap unit's positive work at 1 ms, 3.5 % of hover_1's).
// What a joint transmits can be read off the states instead. Over a (sub)step, about the
// mean of its start's and end's axis (and a point on it), the angular momentum of the bodies
// beyond the joint (its subtree, with the fluid their plates carry) changes by what the joint
// transmits plus the external impulses on them; the difference of two states is second order.
// The motor's work is what the joint transmits less its spring and implicit damping:
//
//   W = (a . dL - a . J_ext) v_mean - a . M_g dq + k (q_mean - q_ref) dq + d v_end h v_mean
//
// (J_ext: the air's and the user's impulses on the subtree, taken over the mean joint
// velocity as the energy audit takes the air's work; M_g: gravity's moment about the axis at
// the bodies' mean positions, over the joint's move dq, as the potential changes; the spring
// at the mean position, so that its work is the change of its energy; the damping only if it
// acts in the servo solve, as the audit takes it). The momenta are those of the frame of the
// bodies' centre of mass at the (sub)step's start, where the fluid's impulse also turns by its
// drift through the fluid, (U - V) x P_fluid: a step's joint-space straight lines move the
// bodies by other than step x their end velocities, so that another frame's momenta would make
// the work depend on the observer. A prismatic joint: the same with the
// subtree's linear momentum along its axis. A (sub)step in which a contact or a joint limit
// may have acted (their impulses are not known here) takes the servo's impulse instead, and so
// does a creature whose plates carry added mass in a fluid without its velocity products (the
// caller's rule, world/creature_step.cpp: there the momentum balance's rigid correction hands
// the bodies the turning of the fluid's impulse that no force on the plates carries).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <vector>

#include "dynamics/bullet_body.h"
#include "dynamics/spatial.h"
#include "flapsim/creature_model.h"

namespace flapsim {

class CreatureFluid;
class ServoStage;

class TransmittedWork {
 public:
  // For creature `m` (which must outlive it).
  explicit TransmittedWork(const CreatureModel& m);

  // The start of a (sub)step: the state's momenta, unless the last end's are still the state.
  // `density`: of the fluid whose added mass the plates carry (0: none), moving at
  // `fluid_velocity` (world frame).
  void beginSubStep(BulletBody& body, CreatureFluid& fluid, double density,
                    const Vec3& fluid_velocity);
  // An impulse on link `link` over the (sub)step: [moment about `com`; force], `com` the
  // link's COM at the (sub)step's start.
  void addImpulse(int link, const Vec3& com, const Vec6& impulse);
  // The end of a (sub)step of `h` (after the momentum balance): the end state's momenta, and the
  // air's impulses (`air`: the fluid stage ran). `constrained`: a contact or a joint limit may
  // have acted in it.
  void endSubStep(BulletBody& body, CreatureFluid& fluid, const ServoStage& servos, bool air,
                  const Vec3& gravity, bool constrained, double h);
  // After endSubStep(): whether the (sub)step's works are known (no contact or limit acted).
  bool known() const { return known_; }
  // After endSubStep() with known(): joint `joint`'s motor work over it (J).
  double work(size_t joint, const ServoStage& servos, const btMultiBody& mb, double h) const;
  // The state was set from outside a step: the next start is measured again.
  void forget() { valid_ = false; }

 private:
  // A body's momentum, world frame: its COM, linear momentum, and angular momentum about its
  // COM, each with the fluid it carries.
  struct BodyMomentum {
    Vec3 com = Vec3::Zero();
    Vec3 linear = Vec3::Zero();
    Vec3 angular = Vec3::Zero();
    Vec3 fluid_linear = Vec3::Zero();  // the fluid's share of `linear`
  };
  // A joint's axis (unit, world frame), a point on it, and its position.
  struct JointPlace {
    JointAxis place;
    double position = 0.0;
  };
  struct Snapshot {
    Vec3 centre_velocity = Vec3::Zero();  // of the bodies' common COM
    std::vector<BodyMomentum> bodies;     // per model link
    std::vector<JointPlace> joints;       // per model joint (movable ones)
  };
  void take(BulletBody& body, CreatureFluid& fluid, Snapshot& out);

  const CreatureModel& model_;
  std::vector<std::vector<int>> subtree_;  // per model joint: its child link and all beyond
  std::vector<char> metered_;              // per link: beyond some joint (its momentum counts)
  std::vector<Vec3> velocity_, omega_;     // per link, world frame: take()'s scratch
  Snapshot start_, end_;
  bool valid_ = false;  // end_ of the last (sub)step is the state's (the next start)
  bool known_ = false;
  double density_ = 0.0;
  Vec3 fluid_velocity_ = Vec3::Zero();
  Vec3 origin_ = Vec3::Zero();  // the root COM at the (sub)step's start
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> impulse_;  // per link: [moment; force]
  std::vector<Vec3> start_com_;  // per link: its COM at the (sub)step's start
  Vec3 gravity_ = Vec3::Zero();
};

}  // namespace flapsim
