// Buoyancy (the paper's rho V g), a fluid law (fluid/fluid_law.h). Private to flapsim_core.
#pragma once

#include "fluid/fluid_law.h"

namespace flapsim {

/// Buoyancy rho V g opposite to gravity (gravity is a vector, e.g. (0,0,-9.81)).
inline Vec3 buoyancyForce(double volume, double density, const Vec3& gravity) {
  return -density * volume * gravity;
}

/// Buoyancy of a body as a wrench about its COM (world frame): the force -rho V g of the
/// surface's displaced volume, acting at its centroid, so torque (R centroid) x force.
Wrench buoyancyLaw(const FluidInput& in, std::vector<Vec3>* cell_forces);

}  // namespace flapsim
