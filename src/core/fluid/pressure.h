// The paper's pressure law (IEEE SMC 2010, eq. 3): pressure on the sub-surfaces that advance
// into the air, a fluid law (fluid/fluid_law.h), and its linearisation, which the world
// treats implicitly. Private to flapsim_core.
#pragma once

#include <vector>

#include "dynamics/spatial.h"
#include "fluid/fluid_law.h"

namespace flapsim {

/// The paper's pressure on one cell (world frame): zero unless the face
/// advances into the air (u.n > 0), then -1/2 rho Cd s |u| (u.n) n.
inline double pressureMagnitude(const Vec3& u, const Vec3& n, double area, double density,
                                double cd) {
  const double un = u.dot(n);
  return un > 0.0 ? 0.5 * density * cd * area * u.norm() * un : 0.0;
}
inline Vec3 pressureForce(const Vec3& u, const Vec3& n, double area, double density, double cd) {
  return -pressureMagnitude(u, n, area, density, cd) * n;
}

/// The pressure on every advancing cell of the body, summed: on a regular grid face the
/// relative velocity is affine in the cell index, so a cell costs a few multiply-adds and
/// one square root.
Wrench pressureLaw(const FluidInput& in, std::vector<Vec3>* cell_forces);

/// Linearised normal drag of the pressure law, about the body's COM in world axes: for
/// each advancing cell, the derivative of its normal force magnitude by its normal speed,
/// 1/2 rho Cd s (|u| + (u.n)^2 / |u|), as a weight along the cell normal. Times the step,
/// it is the damping the world treats implicitly (a stabiliser: the air forces themselves
/// are evaluated by the law at the start of the step).
Mat6 pressureDragDamping(const FluidInput& in);

/// The paper's model (IEEE SMC 2010, eq. 3): pressure on advancing sub-surfaces, stabilised
/// with its own derivative (pressureDragDamping); it reads the surface's drag coefficient.
class PressureAirModel : public LawAirModel<pressureLaw> {
 public:
  AirLinearisation linearisation() const override { return AirLinearisation::kOwn; }
  AirDamping dragDamping(const BodyKinematics& body, const AeroSurface& surface,
                         const AirParams& air) const override {
    return pressureDragDamping(FluidInput{body, surface, air});
  }
  bool readsDragCoefficient() const override { return true; }
  bool forcesAlongNormals() const override { return true; }
  std::string check(const AirParams& air) const override;
};

}  // namespace flapsim
