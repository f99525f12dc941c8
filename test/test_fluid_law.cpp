// One contract per fluid law (flapsim/air_model.h): a law of one's own is one class and one
// registerAirModel line; the world stabilises a stiff law with the law's own linearisation,
// with central differences of its kernel, or not at all, as the law says -- never with
// another law's (before, every law got the pressure law's).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "flapsim/world.h"
#include "fluid/added_mass.h"
#include "fluid/creature_fluid.h"
#include "fluid/fluid_law.h"
#include "fluid/pressure.h"
#include "fluid/surface.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

Mat3 cross(const Vec3& r) {
  Mat3 m;
  m << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return m;
}

// Linear drag on every cell, F = -c rho s u (s: the cell's area, u: its velocity relative to
// the air), with its exact derivative; a law of our own, in this file only.
class LinearDrag : public AirModel {
 public:
  LinearDrag(double c, AirLinearisation linearisation) : c_(c), linearisation_(linearisation) {}
  Wrench bodyWrench(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                    std::vector<Vec3>* cell_forces) const override {
    Wrench w;
    if (cell_forces) cell_forces->clear();
    for (const SurfaceCell& cell : surface.cells) {
      const Vec3 r = body.orientation * cell.centre;
      const Vec3 f = -c_ * air.density * cell.area *
                     relativeAirVelocity(body.linear_velocity, body.angular_velocity, r, air.wind);
      w.force += f;
      w.torque += r.cross(f);
      if (cell_forces) cell_forces->push_back(f);
    }
    return w;
  }
  AirLinearisation linearisation() const override { return linearisation_; }
  // -dW/dnu per cell, k = c rho s: [[-k [r]^2, k [r]], [-k [r], k 1]].
  AirDamping dragDamping(const BodyKinematics& body, const AeroSurface& surface,
                         const AirParams& air) const override {
    AirDamping d = AirDamping::Zero();
    for (const SurfaceCell& cell : surface.cells) {
      const double k = c_ * air.density * cell.area;
      const Mat3 rx = cross(body.orientation * cell.centre);
      d.topLeftCorner<3, 3>() -= k * rx * rx;
      d.topRightCorner<3, 3>() += k * rx;
      d.bottomLeftCorner<3, 3>() -= k * rx;
      d.bottomRightCorner<3, 3>() += k * Mat3::Identity();
    }
    return d;
  }
  // Linear, not quadratic: as stiff as a quadratic law of a huge coefficient (always treated
  // implicitly when it says how).
  double forceCoefficient(const AeroSurface&, const AirParams&) const override { return 1e9; }

 private:
  double c_;
  AirLinearisation linearisation_;
};

constexpr double kPlateMass = 0.01;  // plate.urdf

// Water without buoyancy or added mass, no ground: only the law acts besides gravity.
WorldParams lawOnlyWater() {
  WorldParams p = test::openSky();
  p.ground = false;
  p.air = waterParams();
  p.air.buoyancy = false;
  p.air.added_mass = false;
  return p;
}

// The plate (0.2 x 0.2 x 0.002 m, 10 g) falling flat from rest in lawOnlyWater() under `law`
// for `steps` of 1 ms: its vertical velocity.
double fallingPlateVelocity(const AirModelPtr& law, int steps) {
  World w(lawOnlyWater());
  w.setAirModel(law);
  w.spawn("plate", loadUrdf("plate.urdf"), at(0, 0, 5));
  w.step(steps);
  return w.rootTwist("plate").linear.z();
}

// The drag rate k = c rho (sum of the cell areas) of LinearDrag on the plate in water.
double plateDragRate(double c) {
  const CreatureModelPtr m = loadUrdf("plate.urdf");
  double area = 0.0;
  for (const SurfaceCell& cell : linkAeroSurface(*m, 0, waterParams()).cells) area += cell.area;
  return c * 1000.0 * area;
}

// The plate's velocity after n steps of dt under linear drag k, m (v1 - v0) = dt (-m g - k v0)
// - dt k (v1 - v0) / 2 (the law's damping over half the step) once it moves: at rest the
// stiffness test (rate proportional to the speed) sees no drag, and the first step is free fall.
double trapezoidalFall(double k, double dt, int n) {
  const double g = 9.81;
  double v = -g * dt;
  for (int i = 1; i < n; ++i)
    v += dt * (-g - k / kPlateMass * v) / (1.0 + 0.5 * dt * k / kPlateMass);
  return v;
}

// Stiff (dt k / m = 8.2: the explicit step would grow each step by 7.2): the world takes the
// law's own damping over half the step to rounding (measured 2e-16 m/s), and the plate settles
// at the terminal speed m g / k.
TEST(FluidLaw, AStiffLawIsSolvedWithItsOwnLinearisation) {
  const double c = 1.0, k = plateDragRate(c), dt = 0.001, g = 9.81;
  ASSERT_GT(dt * k / kPlateMass, 8.0);
  const auto law = std::make_shared<LinearDrag>(c, AirLinearisation::kOwn);
  for (int n = 1; n <= 20; ++n) {
    EXPECT_NEAR(fallingPlateVelocity(law, n), trapezoidalFall(k, dt, n), 1e-14) << n;
  }
  EXPECT_NEAR(fallingPlateVelocity(law, 200), -kPlateMass * g / k, 1e-12);
}

// A law that declares no linearisation is evaluated explicitly, stiff water or not:
// m (v1 - v0) = dt (-m g - k v0) exactly (dt k / m = 0.41 here).
TEST(FluidLaw, ALawWithoutALinearisationIsExplicit) {
  const double c = 0.05, k = plateDragRate(c), dt = 0.001, g = 9.81;
  const auto law = std::make_shared<LinearDrag>(c, AirLinearisation::kNone);
  double v = 0.0;
  for (int n = 1; n <= 20; ++n) {
    v += dt * (-g - k / kPlateMass * v);
    EXPECT_NEAR(fallingPlateVelocity(law, n), v, 1e-14) << n;
  }
}

// Central differences of a kernel give its derivative: for the linear law the exact one (to
// 1e-9 of its largest entry), for the pressure law on a plate moving face-on its own
// linearisation (which keeps only the normal part, exact when u is along n; to 1e-6).
TEST(FluidLaw, FiniteDifferencesMatchTheLawsOwnDerivative) {
  const CreatureModelPtr m = loadUrdf("plate.urdf");
  AirParams air = waterParams();
  const AeroSurface surface = linkAeroSurface(*m, 0, air);
  BodyKinematics body;
  body.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 0).normalized()));
  body.com = Vec3(0, 0, 5);
  body.linear_velocity = Vec3(0.2, -0.1, 0.3);
  body.angular_velocity = Vec3(0.5, -0.2, 0.1);
  const LinearDrag linear(0.7, AirLinearisation::kFiniteDifference);
  const AirDamping exact = linear.dragDamping(body, surface, air);
  const AirDamping fd = finiteDifferenceDamping(linear, body, surface, air);
  EXPECT_LT((fd - exact).norm(), 1e-9 * exact.cwiseAbs().maxCoeff());
  EXPECT_EQ(lawDamping(linear, body, surface, air), fd);

  const PressureAirModel pressure;
  BodyKinematics face_on;
  face_on.orientation = body.orientation;
  face_on.com = body.com;
  face_on.linear_velocity = body.orientation * Vec3(0, 0, -0.4);  // along -n: the bottom face
  const AirDamping own = pressure.dragDamping(face_on, surface, air);
  const AirDamping diff = finiteDifferenceDamping(pressure, face_on, surface, air);
  ASSERT_GT(own.norm(), 0.0);
  EXPECT_LT((diff - own).norm(), 1e-6 * own.norm());
  EXPECT_EQ(lawDamping(pressure, face_on, surface, air), own);
}

// The stiffness test weighs a law's drag against the mass that resists it. The pressure law
// pushes each cell along its normal, and along a plate's normal the plate carries its added
// mass, which the velocity update holds implicitly: the plate (10 g) in water resists its
// faces' drag with 10 g plus 3.64 kg of water, its edges' with its own 10 g. A law whose
// forces leave the normals (quasi-steady lift), or no added mass: the link's own mass, exactly.
TEST(FluidLaw, ThePressureLawsStiffnessTestCountsTheWaterAPlateCarriesAlongItsNormal) {
  const CreatureModelPtr m = loadUrdf("plate.urdf");  // 0.2 x 0.2 x 0.002 m
  AeroBody a = CreatureFluid(*m, waterParams()).bodies()[0];
  const double faces = 2 * 0.2 * 0.2, edges = 4 * 0.2 * 0.002;
  ASSERT_NEAR(a.area, faces + edges, 1e-15);
  const double carried = plateAddedMass(1000.0, 0.2, 0.2);
  EXPECT_NEAR(carried, 0.579 * 1000.0 * M_PI * 0.2 * 0.2 * 0.2 / 4, 1e-12);  // DNV C_A = 0.579
  const double resisting = (faces + edges) / (faces / (kPlateMass + carried) + edges / kPlateMass);
  EXPECT_NEAR(dragMass(a, 1000.0, true), resisting, 1e-12 * resisting);
  EXPECT_GT(dragMass(a, 1000.0, true), 0.4);  // the edges' 2 % of the area keep it far below
  EXPECT_EQ(dragMass(a, 1000.0, false), kPlateMass);
  EXPECT_EQ(dragMass(a, 0.0, true), kPlateMass);
  AirParams bare = waterParams();
  bare.added_mass = false;
  AeroBody without = CreatureFluid(*m, bare).bodies()[0];
  EXPECT_EQ(dragMass(without, 1000.0, true), kPlateMass);
  EXPECT_TRUE(PressureAirModel().forcesAlongNormals());
  EXPECT_FALSE(makeAirModel("quasi_steady")->forcesAlongNormals());
}

// So the plate thrown face-down at 1 m/s through water with its added mass (dt rho C A |u| /
// m = 9.4 for its own mass, 0.03 with the water it carries) is stepped explicitly:
// (m + m_a) (v1 - v0) = dt (-m g + rho C A_face v0^2 / 2), step by step to rounding. Its own
// 10 g alone would have taken the linearised drag: 4e-5 m/s off in the first step.
TEST(FluidLaw, APlateThrownThroughWaterIsSteppedExplicitlyWithTheWaterItCarries) {
  WorldParams p = lawOnlyWater();
  p.air.added_mass = true;
  const CreatureModelPtr m = loadUrdf("plate.urdf");
  const double carried = plateAddedMass(1000.0, 0.2, 0.2), dt = 0.001, g = 9.81;
  const double k = 0.5 * 1000.0 * p.air.drag_coefficient * 0.2 * 0.2;  // one face advances
  Twist thrown;
  thrown.linear = Vec3(0, 0, -1.0);
  double v = -1.0;
  for (int n = 1; n <= 20; ++n) {
    World w(p);
    w.spawn("plate", m, at(0, 0, 5), thrown);
    w.step(n);
    v += dt * (-kPlateMass * g + k * v * v) / (kPlateMass + carried);
    EXPECT_NEAR(w.rootTwist("plate").linear.z(), v, 1e-13) << n;
  }
}

// Registered once, a law is named like the built-in ones: by AirParams::model and by a link's
// <aero model="...">, which then flies with it while the world's default is the pressure law.
TEST(FluidLaw, ARegisteredLawIsChosenByName) {
  const double c = 1.0, k = plateDragRate(c), dt = 0.001;
  registerAirModel("linear_drag_test", std::make_shared<LinearDrag>(c, AirLinearisation::kOwn));
  EXPECT_NE(makeAirModel("linear_drag_test"), nullptr);
  try {
    registerAirModel("linear_drag_test", std::make_shared<LinearDrag>(c, AirLinearisation::kOwn));
    ADD_FAILURE() << "a taken name was registered again";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "air model 'linear_drag_test' is already registered");
  }
  EXPECT_EQ(unknownAirModelMessage("x"),
            "unknown air model 'x' (pressure, quasi_steady, linear_drag_test)");

  std::ifstream file(test::sourcePath("urdf/plate.urdf"));
  std::string urdf((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::string aero = R"(<aero link="plate" subdivisions="4 4"/>)";
  ASSERT_NE(urdf.find(aero), std::string::npos);
  urdf.replace(urdf.find(aero), aero.size(),
               R"(<aero link="plate" subdivisions="4 4" model="linear_drag_test"/>)");
  World w(lawOnlyWater());
  w.spawn("plate", parseCreatureModel(urdf), at(0, 0, 5));
  w.step(20);
  EXPECT_NEAR(w.rootTwist("plate").linear.z(), trapezoidalFall(k, dt, 20), 1e-14);
}

}  // namespace
}  // namespace flapsim
