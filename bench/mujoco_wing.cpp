// mujoco_wing: the hover creature's wing membrane (a flat plate, chord x span x thickness of
// flapsim::HoverParams) in MuJoCo's ellipsoid fluid model (the MuJoCo the build found, opened
// at run time: bench/mujoco_api.h) and in flapsim's two air
// models, on the same plate in the same two situations:
//   1. translating at U = 5 m/s through still air (density 1.204) at angles of attack from 0 to
//      90 deg, pitched about its span: the lift and drag coefficients F / (1/2 rho U^2 S), S =
//      chord x span, each model's force at that instant (MuJoCo: qfrc_passive of a free body
//      after mj_forward; flapsim: the air wrench of one step, World::aeroForces);
//   2. released at rest, level, in water (density 1000) without gravity's help other than its
//      own weight: the start acceleration against momentum theory's (m - rho V) g / (m + m_a),
//      m_a = C_A rho pi c^2 b / 4 (DNV-RP-C205 table A-2).
// Prints a table; never passes or fails. Used by doc/validation.md.
//
//   mujoco_wing
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "flapsim/make_creature.h"
#include "flapsim/world.h"
#include "mujoco_api.h"

using flapsim_bench::mj;

namespace {

constexpr double kSpeed = 5.0;  // m/s

// The membrane as a URDF creature: one link, the quasi-steady or pressure model, span y.
std::string plateUrdf(const flapsim::HoverParams& p, const std::string& model) {
  std::ostringstream out;
  out << "<robot name=\"wing\"><link name=\"plate\"><inertial><mass value=\"" << p.wing_mass
      << "\"/><inertia ixx=\"1e-8\" ixy=\"0\" ixz=\"0\" iyy=\"1e-8\" iyz=\"0\" izz=\"1e-8\"/>"
      << "</inertial><collision><geometry><box size=\"" << p.wing_chord << ' ' << p.wing_span << ' '
      << p.wing_thickness << "\"/></geometry></collision></link>"
      << "<aero link=\"plate\" model=\"" << model << "\" span=\"y\"/></robot>";
  return out.str();
}

std::string plateMjcf(const flapsim::HoverParams& p, double density, double gravity) {
  std::ostringstream out;
  out << "<mujoco><option timestep=\"0.0001\" gravity=\"0 0 " << -gravity << "\" density=\""
      << density << "\" viscosity=\"0\"/><worldbody><body name=\"plate\"><freejoint/>"
      << "<inertial pos=\"0 0 0\" mass=\"" << p.wing_mass << "\" diaginertia=\"1e-8 1e-8 1e-8\"/>"
      << "<geom type=\"box\" size=\"" << 0.5 * p.wing_chord << ' ' << 0.5 * p.wing_span << ' '
      << 0.5 * p.wing_thickness
      << "\" contype=\"0\" conaffinity=\"0\" "
         "fluidshape=\"ellipsoid\"/></body></worldbody></mujoco>";
  return out.str();
}

// MuJoCo's fluid force (world frame) on the plate pitched `alpha` (nose up) moving at +x.
flapsim::Vec3 mujocoForce(const flapsim::HoverParams& p, double alpha) {
  mjModel* m = flapsim_bench::compileMjcf(plateMjcf(p, 1.204, 0.0));
  mjData* d = mj.makeData(m);
  // Nose up: the leading (+x) edge up, a rotation about -y.
  d->qpos[3] = std::cos(alpha / 2);
  d->qpos[5] = -std::sin(alpha / 2);
  d->qvel[0] = kSpeed;
  mj.forward(m, d);
  const flapsim::Vec3 f(d->qfrc_passive[0], d->qfrc_passive[1], d->qfrc_passive[2]);
  mj.deleteData(d);
  mj.deleteModel(m);
  return f;
}

// flapsim's air force on the same plate, with the air model `model`.
flapsim::Vec3 flapsimForce(const flapsim::HoverParams& p, double alpha, const std::string& model) {
  flapsim::WorldParams w;
  w.ground = false;
  w.gravity = flapsim::Vec3::Zero();
  w.air.added_mass = false;
  w.air.buoyancy = false;
  flapsim::World world(w);
  flapsim::Twist twist;
  twist.linear = flapsim::Vec3(kSpeed, 0, 0);
  world.spawn("plate", flapsim::parseCreatureModel(plateUrdf(p, model)),
              flapsim::Pose{flapsim::Vec3(0, 0, 10),
                            flapsim::Quat(Eigen::AngleAxisd(alpha, -flapsim::Vec3::UnitY()))},
              twist);
  world.step(1);
  return world.aeroForces("plate").at(0).wrench.force;
}

}  // namespace

int main() {
  if (!flapsim_bench::openMujoco(FLAPSIM_MUJOCO_LIBRARY, "mujoco_wing")) return 1;
  *mj.user_warning = flapsim_bench::warningToStderr;
  std::printf("MuJoCo %s\n", mj.versionString());
  const flapsim::HoverParams p;
  const double area = p.wing_chord * p.wing_span, q = 0.5 * 1.204 * kSpeed * kSpeed * area;
  std::printf("plate %g x %g x %g m (the hover wing), %g m/s, coefficients F / (1/2 rho U^2 S)\n",
              p.wing_chord, p.wing_span, p.wing_thickness, kSpeed);
  std::printf("%6s | %8s %8s | %8s %8s | %8s %8s\n", "alpha", "qs C_L", "qs C_D", "mj C_L",
              "mj C_D", "pr C_L", "pr C_D");
  for (double deg : {0.0, 5.0, 10.0, 20.0, 30.0, 37.0, 45.0, 60.0, 75.0, 90.0}) {
    const double a = deg * M_PI / 180.0;
    const flapsim::Vec3 qs = flapsimForce(p, a, "quasi_steady");
    const flapsim::Vec3 mj = mujocoForce(p, a);
    const flapsim::Vec3 pr = flapsimForce(p, a, "pressure");
    std::printf("%6.0f | %8.3f %8.3f | %8.3f %8.3f | %8.3f %8.3f\n", deg, qs.z() / q, -qs.x() / q,
                mj.z() / q, -mj.x() / q, pr.z() / q, -pr.x() / q);
  }
  // Released at rest, level, in water.
  const double rho = 1000.0, g = 9.81, m = p.wing_mass;
  const double volume = p.wing_chord * p.wing_span * p.wing_thickness;
  // C_A at b / a = 0.12 / 0.045 = 2.67, linear in a / b between 2.5 (0.801) and 3 (0.830).
  const double ratio = p.wing_span / p.wing_chord;
  const double ca = 0.801 + (0.830 - 0.801) * (1.0 / ratio - 1.0 / 2.5) / (1.0 / 3.0 - 1.0 / 2.5);
  const double added = ca * rho * M_PI * p.wing_chord * p.wing_chord * p.wing_span / 4.0;
  const double expected = (m - rho * volume) * -g / (m + added);
  mjModel* mm = flapsim_bench::compileMjcf(plateMjcf(p, rho, g));
  mjData* d = mj.makeData(mm);
  mj.step(mm, d);
  const double mujoco = d->qvel[2] / mm->opt.timestep;
  mj.deleteData(d);
  mj.deleteModel(mm);
  flapsim::WorldParams w;
  w.ground = false;
  w.air.density = rho;
  w.step_size = 0.0001;
  flapsim::World world(w);
  world.spawn("plate", flapsim::parseCreatureModel(plateUrdf(p, "quasi_steady")),
              flapsim::Pose{flapsim::Vec3(0, 0, 0), flapsim::Quat::Identity()});
  world.step(1);
  const double ours = world.rootTwist("plate").linear.z() / w.step_size;
  std::printf(
      "released level in water: momentum theory with C_A = %.3f (m_a = %.4g kg, %.0f times "
      "the plate): %.5f m/s^2; flapsim %.5f m/s^2 (%+.2f %%); MuJoCo %.5f m/s^2 (%+.0f %%)\n",
      ca, added, added / m, expected, ours, 100.0 * (ours / expected - 1.0), mujoco,
      100.0 * (mujoco / expected - 1.0));
  return 0;
}
