// The quasi-steady blade-element law (Robofly coefficients, centre-of-pressure shift,
// rotational lift), a fluid law (fluid/fluid_law.h). Private to flapsim_core.
#pragma once

#include <vector>

#include "fluid/fluid_law.h"

namespace flapsim {

/// Angle of attack in [0, 90] deg of a face with normal n moving at u (spanwise part of u
/// removed), and the lift and drag coefficients there.
double angleOfAttack(const Vec3& u_chordwise, const Vec3& n);
double liftCoefficient(double alpha_deg, const QuasiSteadyCoefficients& c);
double dragCoefficient(double alpha_deg, const QuasiSteadyCoefficients& c);

/// Quasi-steady blade-element force on one cell of an advancing face (zero otherwise):
/// with u' = u minus its component along the span s, drag 1/2 rho s_i C_D |u'|^2 against
/// u' and lift 1/2 rho s_i C_L |u'|^2 perpendicular to u' in the chord plane, on the side
/// the face pushes the air from (-n).
Vec3 quasiSteadyForce(const Vec3& u, const Vec3& n, const Vec3& span, double area, double density,
                      const QuasiSteadyCoefficients& c);

/// Whitney & Wood (2010): the centre of pressure of a chordwise strip at angle of attack
/// alpha (degrees, 0..90) lies d_cp / c = 0.82 alpha / 180 + 0.05 from its leading edge.
double centreOfPressureFraction(double alpha_deg);

/// Sane & Dickinson (2002): rotational force coefficient C_rot = pi (0.75 - x0), x0 the
/// pitch axis' distance from the leading edge over the chord.
double rotationalLiftCoefficient(double x0);

/// The quasi-steady blade-element law: per cell, angle of attack from the chordwise
/// velocity; lift and drag from QuasiSteadyCoefficients. Needs AeroSurface::faces.
/// With AirParams::centre_of_pressure_shift, each cell's force acts (c/2 - d_cp) ahead of the
/// cell's centre, towards the leading edge (the chordwise edge the cell moves towards), which
/// puts a uniformly loaded strip's force at d_cp. With AirParams::rotational_lift, each cell
/// of an advancing face also feels C_rot rho U c s_i omega along the face normal, where U and
/// the leading edge are taken at the pitch axis (same span station, so pure pitching about the
/// axis in still air gives none), omega is the angular velocity about the span, positive when
/// it raises the angle of attack, and the force then adds to the translational normal force.
/// Faces without span information (no AeroSurface::faces) get neither.
Wrench quasiSteadyLaw(const FluidInput& in, std::vector<Vec3>* cell_forces);

/// The quasi-steady law as an air model.
/// The quasi-steady law as an air model: stabilised with central differences of its own
/// kernel (its coefficients are fits, with no derivative of their own written here); its
/// force scale is the largest |C_L| + |C_D| its coefficients can give.
class QuasiSteadyAirModel : public LawAirModel<quasiSteadyLaw> {
 public:
  AirLinearisation linearisation() const override { return AirLinearisation::kFiniteDifference; }
  double forceCoefficient(const AeroSurface& surface, const AirParams& air) const override;
  std::string check(const AirParams& air) const override;
};

}  // namespace flapsim
