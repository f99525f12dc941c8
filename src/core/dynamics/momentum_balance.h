// The momentum balance of a creature's step (see dynamics/momentum.h): begin() takes the
// momentum at the start of the (sub)step, the fluid and external stages add their impulses,
// the servo stage the implicit drag's, and end(), after Bullet's step, gives the base the
// rigid correction that makes the momentum and the centre of mass those of the external
// impulses (internal forces then move neither), unless the creature touches something
// (contact impulses are not known here) or is anchored. Private to flapsim_core.
#pragma once

#include <vector>

#include "dynamics/momentum.h"
#include "dynamics/spatial.h"
#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"

namespace flapsim {

class BulletBody;
class CreatureFluid;

class MomentumBalance {
 public:
  explicit MomentumBalance(const CreatureModel& m) : model_(m) {}

  // The start of a (sub)step (frames of its start): the momentum of the tree and of the fluid
  // its plates carry at `added_mass_density` (0: none) in a fluid moving at `fluid_velocity`
  // (world frame; the fluid's momentum is that of each plate's velocity relative to it),
  // carried over from the last corrected step or measured; no impulse yet. A step whose fluid
  // velocity differs from the last one's keeps the carried momentum: the fluid's momentum is
  // then measured against the new velocity at the end, which gives the bodies the added
  // mass's share of the flow's acceleration, A dU (flapsim/fluid_stage.h adds rho V dU).
  // `products`: with Kirchhoff's, carry the angular momentum with the added mass's Munk term;
  // where the plates shed them (kShed) their wrenches are external (addShedProducts) and that
  // term is left out.
  void begin(BulletBody& body, CreatureFluid& fluid, double added_mass_density,
             const Vec3& fluid_velocity, AddedMassProducts products);
  // A wrench about the COM `com` of a link (frames of the step's start) acting all step.
  void addExternal(const Vec3& com, const Wrench& wrench);
  // The velocity products a plate sheds into the wake, taken at the step's start (about its
  // COM `com`, less the creature's share of their moment, (V - U) x p): an external wrench
  // whose impulse end() takes by the trapezoidal rule, with the same wrench at the step's end
  // (Heun's predictor: Bullet's end velocities before the correction). Taken at the start
  // alone, the impulse was first order in the step and the flap unit's climb 2-9 % short at
  // 1-2 ms with the stroke's turns in substeps.
  void addShedProducts(const Vec3& com, const Wrench& wrench);
  // The implicit drag's impulse over the step [moment about the root COM of the step's start;
  // force] (the servo stage's solve).
  void setDragImpulse(const Vec6& impulse) { drag_impulse_ = impulse; }
  // After Bullet's step: the correction, and the frames of the step's end in `body`.
  void end(BulletBody& body, CreatureFluid& fluid, const Vec3& gravity, double dt);
  // A corrected step ends with a known momentum, which the next begin() takes instead of
  // measuring it; call this after changing the multibody's state between steps.
  void forget() { carried_valid_ = false; }

 private:
  // The momentum of the tree and of the fluid it carries, at the multibody's state (the
  // scene's TreeDynamics frames, which the next lean step's velocity update reuses). With
  // `shed_end` (at the end of a step of `dt`): also adds to it the products the plates shed at
  // this state, as addShedProducts takes them at the start, [moment about O, the start's
  // origin_ moved with the fluid by U dt; force], and makes each plate's wrench of the step
  // the mean of its start's and this (CreatureFluid::holdMeanShedProducts).
  SystemMomentum measure(BulletBody& body, CreatureFluid& fluid, Vec6* shed_end = nullptr,
                         double dt = 0.0);

  // What the balance keeps of a SystemMomentum from one step to the next (not its matrices:
  // copying them each step cost more than the rest of begin()).
  struct Carried {
    double mass = 0.0;
    Vec3 com = Vec3::Zero();
    Vec3 linear = Vec3::Zero();
    Vec3 angular = Vec3::Zero();
  };

  const CreatureModel& model_;
  // This step's balance: the start, and the external impulses so far (moments about the root
  // COM at the start of the step, `origin_`).
  Carried start_;
  Carried carried_;  // of the end of the last corrected step
  bool carried_valid_ = false;
  double carried_density_ = 0.0;
  double density_ = 0.0;                // of the added mass in this step
  Vec3 fluid_velocity_ = Vec3::Zero();  // the fluid's, in this step
  AddedMassProducts products_ = AddedMassProducts::kShed;
  Vec3 origin_ = Vec3::Zero();
  Vec3 external_force_ = Vec3::Zero();
  Vec3 external_moment_ = Vec3::Zero();
  // The shed products' wrench at the step's start, the sum of addShedProducts [moment about
  // origin_; force].
  Vec6 shed_start_ = Vec6::Zero();
  Vec6 drag_impulse_ = Vec6::Zero();
  // Scratch, kept between steps: no allocation once warm.
  struct LinkMotion {  // of a link's COM, world frame
    Vec3 com = Vec3::Zero();
    Vec3 velocity = Vec3::Zero();
    Vec3 angular_velocity = Vec3::Zero();
  };
  std::vector<LinkMotion> motions_;
};

}  // namespace flapsim
