// The fluid stage of a step: once per (sub)step, the air's explicit wrenches on a creature's
// aero bodies (the fluid laws of src/core/fluid/, the world's model or a link's own) applied
// to its Bullet body and to its momentum balance, and this step's implicit part (added mass,
// linearised drag) for the servo stage. Private to flapsim_core.
#pragma once

#include <string>
#include <utility>

#include "flapsim/air_model.h"
#include "flapsim/world.h"
#include "fluid/creature_fluid.h"

namespace flapsim {

class BulletBody;
class MomentumBalance;

// The air models in use: the world's default (the links that name their own hold it,
// AeroBody::own_model).
class AirStage {
 public:
  explicit AirStage(const std::string& default_model);

  void setDefaultModel(AirModelPtr model);
  void setRecordCells(bool on) { record_cells_ = on; }

  // The fluid stage of a (sub)step of `step` seconds: adds the air's wrench (and buoyancy) to
  // every aero body of `body` (frames of the step's start) and to the momentum balance,
  // records it in the aero body's `last`, and sets this step's implicit part. Without air,
  // none of it (the fluid is inactive).
  void apply(const CreatureModel& model, BulletBody& body, CreatureFluid& fluid,
             MomentumBalance& momentum, const WorldParams& params, double step) const;

 private:
  const AirModel& modelOf(const AeroBody& a) const {
    return a.own_model ? *a.own_model : *default_model_;
  }
  // Adds to `w` what aero body `i`'s added mass does beyond the servo stage's -A dnu
  // (fluid_stage.cpp); `centre_velocity`: the creature's centre of mass's.
  static void addAddedMass(const CreatureModel& model, BulletBody& body, CreatureFluid& fluid,
                           MomentumBalance& momentum, const AirParams& air, size_t i,
                           const Vec3& centre_velocity, Wrench& w);

  AirModelPtr default_model_;
  bool record_cells_ = false;
};

}  // namespace flapsim
