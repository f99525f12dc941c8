// The fluid's laws, one kernel each (after MuJoCo's fluid model: pure functions of a body's
// motion). The explicit laws -- the paper's pressure (fluid/pressure.h), the quasi-steady
// blade element (fluid/quasi_steady.h) and buoyancy (fluid/buoyancy.h) -- share one
// signature, FluidLaw: the wrench a law exerts on one rigid body about its centre of mass, in
// the world frame, from the body's kinematics, its aero surface and the fluid, and, when asked
// for, each cell's share. An air model (flapsim/air_model.h) wraps a law with the rest of its
// contract: its linearisation for the implicit solve (the pressure law its own derivative,
// the quasi-steady law central differences of its kernel), its force scale, the parameters it
// reads and their checks; fluid/air_models.cpp registers each (one line). The fluid's other
// implicit part is the plates' added mass (fluid/added_mass.h, an inertia constant in the
// body frame). Private to flapsim_core.
#pragma once

#include <vector>

#include "flapsim/air_model.h"
#include "flapsim/types.h"

namespace flapsim {

/// What a fluid law reads: one rigid body's motion and surface, the fluid, and gravity.
struct FluidInput {
  const BodyKinematics& body;
  const AeroSurface& surface;
  const AirParams& air;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
};

/// A fluid law: the wrench about the body's COM (world frame); with `cell_forces`, the force on
/// each cell of the surface (world frame; a law acting on the whole body leaves them).
using FluidLaw = Wrench (*)(const FluidInput& in, std::vector<Vec3>* cell_forces);

/// A law as an air model (flapsim/air_model.h), for the world's and the links' choice; the
/// rest of its contract is AirModel's defaults unless a subclass says otherwise.
template <FluidLaw law>
class LawAirModel : public AirModel {
 public:
  Wrench bodyWrench(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                    std::vector<Vec3>* cell_forces) const override {
    return law(FluidInput{body, surface, air}, cell_forces);
  }
};

/// -d(wrench)/d(motion) of `model` by central differences of its bodyWrench in each of the six
/// components of the body's motion [omega; v] (steps scaled by its speed and its surface's
/// reach), made symmetric and positive semi-definite (negative eigenvalues dropped: an
/// implicit push that adds energy would not stabilise anything).
AirDamping finiteDifferenceDamping(const AirModel& model, const BodyKinematics& body,
                                   const AeroSurface& surface, const AirParams& air);

/// The damping the world treats implicitly for `model` (AirModel::linearisation): its own,
/// its finite differences, or zero for kNone.
AirDamping lawDamping(const AirModel& model, const BodyKinematics& body, const AeroSurface& surface,
                      const AirParams& air);

/// Whether `model` is the registered pressure law, whose wrench the fluid's PressureBatch
/// computes for all such bodies of a creature at once.
bool batchedPressureLaw(const AirModel& model);

}  // namespace flapsim
