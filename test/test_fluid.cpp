// The fluid's implicit part as pure functions (added mass of plates, linearised drag), and
// then in the world: water that stays stable, a plate's initial acceleration with its added
// mass, buoyancy that rights a bottom-heavy body.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "doc_figure.h"
#include "fluid/added_mass.h"
#include "fluid/pressure.h"
#include "fluid/surface.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

constexpr double kWater = 1000.0;

// DNV-RP-C205 table A-2's coefficients at its rows, linear in c / b between them, and the
// plate's added mass C_A rho pi c^2 b / 4 with c the shorter edge.
TEST(AddedMass, CoefficientFollowsTheDnvTableOfRectangularPlates) {
  double most = 0.0;  // the largest difference from the table over its rows
  const double rows[][2] = {{1, 0.579}, {1.25, 0.642}, {1.5, 0.690}, {1.59, 0.704},
                            {2, 0.757}, {2.5, 0.801},  {3, 0.830},   {4, 0.871},
                            {5, 0.897}, {6.25, 0.917}, {8, 0.934},   {10, 0.947}};
  for (const auto& row : rows) {
    most = std::max(most, std::abs(plateAddedMassCoefficient(1.0, row[0]) - row[1]));
  }
  test::printFigure("largest_difference", most);
  EXPECT_DOUBLE_EQ(plateAddedMassCoefficient(0.2, 0.2), 0.579);
  EXPECT_DOUBLE_EQ(plateAddedMassCoefficient(0.1, 0.2), 0.757);
  EXPECT_DOUBLE_EQ(plateAddedMassCoefficient(0.3, 0.1), 0.830);  // either edge first
  EXPECT_DOUBLE_EQ(plateAddedMassCoefficient(0.1, 1.0), 0.947);
  // b / c = 2.25: c / b = 0.444, between the rows c / b = 0.5 (0.757) and 0.4 (0.801).
  const double r = 1.0 / 2.25;
  EXPECT_NEAR(plateAddedMassCoefficient(1.0, 2.25), 0.757 + (0.801 - 0.757) * (0.5 - r) / 0.1,
              1e-12);
  // b / c = 20: half way in c / b from 1/10 (0.947) to the infinite strip (1).
  EXPECT_NEAR(plateAddedMassCoefficient(0.05, 1.0), 0.9735, 1e-12);
  EXPECT_NEAR(plateAddedMass(1000.0, 0.1, 0.3), 0.830 * 1000.0 * M_PI * 0.01 * 0.3 / 4.0, 1e-12);
}

// A plate's added mass, spread over its mid-plane, sums to the strip-theory value and acts
// only along its normal; a cube gets none.
TEST(AddedMass, PlateGetsItAlongItsNormalOnly) {
  std::vector<NormalMass> masses;
  const Pose tilted{Vec3(0.1, 0, 0), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY()))};
  appendPlateAddedMass(masses, Vec3(0.22, 0.35, 0.002), tilted, 4, 4);
  ASSERT_EQ(masses.size(), 16u);
  const Mat6 a = normalInertia(masses, kWater);
  const Vec3 n = tilted.orientation * Vec3::UnitZ();
  const double expected = plateAddedMass(kWater, 0.22, 0.35);
  const Vec3 in_plane = tilted.orientation * Vec3::UnitX();
  test::printFigure("normal_relative_error",
                    std::abs(n.dot(a.bottomRightCorner<3, 3>() * n) / expected - 1.0));
  test::printFigure("in_plane_relative",
                    std::abs(in_plane.dot(a.bottomRightCorner<3, 3>() * in_plane)) / expected);
  EXPECT_NEAR(n.dot(a.bottomRightCorner<3, 3>() * n), expected, 1e-12 * expected);
  EXPECT_NEAR(in_plane.dot(a.bottomRightCorner<3, 3>() * in_plane), 0.0, 1e-12 * expected);
  std::vector<NormalMass> cube;
  appendPlateAddedMass(cube, Vec3(0.1, 0.1, 0.1), Pose(), 4, 4);
  EXPECT_TRUE(cube.empty());
}

// An added mass m along z at the plate's COM, the plate moving at v = (vx, 0, vz) and pitching
// at q: h = (0, 0, m vz) linear, and nu x* h gives the force omega x h = (q m vz, 0, 0) and the
// Munk moment v x h = (0, -m vx vz, 0), which together do no work (q (-m vx vz) + vx q m vz). A
// lone plate is the whole creature (V = v): its Munk moment is the creature's share, and only
// the force is external.
TEST(AddedMass, ShedProductsAreTheForceAndMunkMomentAndDoNoWork) {
  const double m = 0.3, vx = 2.0, vz = -0.5, q = 1.5;
  Vec6 f;
  f << Vec3::Zero(), Vec3::UnitZ();
  const SpatialFactor added = factorSpatial(m * f * f.transpose());
  const Vec3 omega(0.0, q, 0.0), v(vx, 0.0, vz);
  const ShedProducts shed = shedProducts(added, omega, v);
  EXPECT_NEAR((shed.linear_momentum - Vec3(0.0, 0.0, m * vz)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((shed.wrench.force - Vec3(q * m * vz, 0.0, 0.0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((shed.wrench.torque - Vec3(0.0, -m * vx * vz, 0.0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(omega.dot(shed.wrench.torque) + v.dot(shed.wrench.force), 0.0, 1e-15);
  const Wrench lone = shed.external(v);
  EXPECT_NEAR((lone.force - shed.wrench.force).norm(), 0.0, 1e-15);
  EXPECT_NEAR(lone.torque.norm(), 0.0, 1e-15);
  // A creature at rest in the fluid keeps the plate's whole moment as external.
  EXPECT_NEAR((shed.external(Vec3::Zero()).torque - shed.wrench.torque).norm(), 0.0, 1e-15);
}

// A plate moving face-on at U: the pressure force is k S U^2 (k = rho Cd / 2), whose
// derivative 2 k S U is the linearised drag along the normal; a retreating face adds none.
TEST(DragDamping, FaceOnPlateIsTheForceDerivative) {
  AeroSurface surface;
  appendBox(surface, Vec3(0.2, 0.3, 0.002), Pose(), 4, 4);
  surface.drag_coefficient = 1.15;
  AirParams air;
  air.density = kWater;
  BodyKinematics body;
  body.linear_velocity = Vec3(0, 0, -2.0);
  const Mat6 d = pressureDragDamping(FluidInput{body, surface, air});
  const double k = 0.5 * kWater * 1.15;
  EXPECT_NEAR(d(5, 5), 2.0 * k * 0.06 * 2.0, 1e-9);
  EXPECT_NEAR(d(3, 3), 0.0, 1e-9);  // the edges (0.002 x 0.3) are parallel to the motion
  // Numerically: the pressure model's force changes by -d(5,5) per m/s of normal speed.
  PressureAirModel model;
  BodyKinematics faster = body;
  faster.linear_velocity.z() -= 1e-6;
  const double dfz = model.bodyWrench(faster, surface, air, nullptr).force.z() -
                     model.bodyWrench(body, surface, air, nullptr).force.z();
  test::printFigure("relative_difference", std::abs(dfz / 1e-6 / d(5, 5) - 1.0));
  EXPECT_NEAR(dfz / 1e-6, d(5, 5), 1e-4 * d(5, 5));
}

// The regular-grid sums give the same matrix as the plain per-cell sum on a tumbling box.
TEST(DragDamping, GridSumsEqualPerCellSum) {
  AeroSurface grid;
  appendBox(grid, Vec3(0.2, 0.3, 0.05), Pose{Vec3(0.01, 0.02, 0), Quat::Identity()}, 5, 3);
  AeroSurface cells = grid;
  cells.faces.clear();
  AirParams air;
  air.wind = Vec3(0.5, -0.2, 0.1);
  BodyKinematics body;
  body.orientation = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  body.linear_velocity = Vec3(1.0, -2.0, 0.5);
  body.angular_velocity = Vec3(20.0, -5.0, 8.0);
  const Mat6 a = pressureDragDamping(FluidInput{body, grid, air});
  const Mat6 b = pressureDragDamping(FluidInput{body, cells, air});
  ASSERT_GT(b.norm(), 1e-3);
  EXPECT_LT((a - b).norm(), 1e-12 * b.norm());
  EXPECT_LT((a - a.transpose()).norm(), 1e-12 * a.norm());  // symmetric
}

// ---- in the world --------------------------------------------------------------------

// A level plate of `chord` x `span` x 2 mm, 10 g, flown by air model `model`.
CreatureModelPtr levelPlate(double chord, double span, const std::string& model) {
  std::ostringstream u;
  u << "<robot name='p'><link name='plate'><inertial><mass value='0.01'/><inertia ixx='1e-5' "
       "ixy='0' ixz='0' iyy='1e-5' iyz='0' izz='2e-5'/></inertial><collision><geometry><box size='"
    << chord << ' ' << span << " 0.002'/></geometry></collision></link><aero link='plate' "
    << "subdivisions='4 4' model='" << model << "' span='y'/></robot>";
  return parseCreatureModel(u.str());
}

// A level plate released at rest in water starts at (m - rho V) g / (m + C_A rho pi c^2 b / 4):
// its weight less buoyancy, against its own mass plus the water it must push (drag is zero
// at rest), C_A that of its aspect ratio in DNV-RP-C205 table A-2: 0.579 for a square plate,
// 0.757 for a 2:1 plate. Within 2 % in both air models, at two step sizes; strip theory's
// C_A = 1 would start the square plate 42 % slower and the 2:1 plate 24 % slower.
TEST(WaterWorld, LevelPlateStartsAtItsAspectRatiosAddedMassAcceleration) {
  struct Plate {
    double chord, span, ca;
  };
  for (const Plate& plate : {Plate{0.2, 0.2, 0.579}, Plate{0.1, 0.2, 0.757}}) {
    for (const char* model : {"pressure", "quasi_steady"}) {
      for (double dt : {0.001, 0.00025}) {
        SCOPED_TRACE(std::to_string(plate.span / plate.chord) + " " + model + " " +
                     std::to_string(dt));
        WorldParams p = test::openSky();
        p.air = waterParams();
        p.step_size = dt;
        World w(p);
        w.spawn("plate", levelPlate(plate.chord, plate.span, model), at(0, 0, 0));
        w.step(1);
        const double m = 0.01, volume = plate.chord * plate.span * 0.002;
        const double added = plate.ca * kWater * M_PI * plate.chord * plate.chord * plate.span / 4;
        const double expected = (m - kWater * volume) * -9.81 / (m + added);
        const double a = w.rootTwist("plate").linear.z() / p.step_size;
        const std::string name =
            test::figureName("%gx%g_%s_%gms", plate.chord, plate.span, model, dt * 1000);
        test::printFigure("a_" + name, a);
        test::printFigure("expected_" + name, expected);
        EXPECT_NEAR(a, expected, 0.02 * std::abs(expected));
        std::printf("plate %g x %g in water (%s), step %g s: a = %.6f m/s^2, C_A = %.3f: %.6f\n",
                    plate.chord, plate.span, model, dt, a, plate.ca, expected);
      }
    }
  }
}

// The swimmer (wings of 76 g carrying ~13 kg of water each) flapping hard for 10 s at 1 ms
// stays finite with a bounded speed; explicit drag without added mass diverged (|z| > 1 km)
// within 0.01 s at w1 = w2 >= 16 rad/s.
TEST(WaterWorld, SwimmerStaysBoundedAtHardStrokes) {
  for (const StrokeCommand& c : {StrokeCommand{40, 40, 0.8}, StrokeCommand{30, 10, 0.8}}) {
    SCOPED_TRACE(std::to_string(c.downstroke_rate) + "/" + std::to_string(c.upstroke_rate));
    WorldParams p = test::openSky();
    p.air = waterParams();
    World w(p);
    w.spawn("s", loadUrdf("swimmer.urdf"), at(0, 0, 0));
    w.setWingCommands("s", {}, {c, c});
    double fastest = 0.0;
    for (int i = 0; i < 10000; ++i) {
      w.step(1);
      fastest = std::max(fastest, w.rootTwist("s").linear.norm());
    }
    const CreatureState s = w.state("s");
    ASSERT_TRUE(s.link_poses[0].position.allFinite());
    // The wing tips move at most 40 rad/s x 0.38 m = 15 m/s relative to the body.
    test::printFigure(test::figureName("fastest_%g/%g", c.downstroke_rate, c.upstroke_rate),
                      fastest);
    EXPECT_LT(fastest, 15.0);
    EXPECT_LT(s.link_poses[0].position.norm(), 10.0);
    std::printf("swimmer %.0f/%.0f: fastest %.2f m/s, at 10 s z = %.3f m\n", c.downstroke_rate,
                c.upstroke_rate, fastest, s.link_poses[0].position.z());
  }
}

// A cube as dense as water with its centre of mass 2 cm below its centre, tilted 30 deg,
// is turned back upright by buoyancy acting at the centroid of the displaced volume (and
// slowed by the water's drag): within 5 deg after 10 s, at 1 and 0.5 ms. With buoyancy at the
// centre of mass it stayed at 30.00 deg.
TEST(WaterWorld, BottomHeavyCubeRightsItself) {
  for (double dt : {0.001, 0.0005}) {
    WorldParams p = test::openSky();
    p.air = waterParams();
    p.step_size = dt;
    World w(p);
    auto cube = parseCreatureModel(R"(<robot name="cube"><link name="c">
    <inertial><origin xyz="0 0 -0.02"/><mass value="1.0"/>
      <inertia ixx="1.67e-3" ixy="0" ixz="0" iyy="1.67e-3" iyz="0" izz="1.67e-3"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link></robot>)");
    w.spawn("cube", cube, at(0, 0, 0, Quat(Eigen::AngleAxisd(30.0 * M_PI / 180.0, Vec3::UnitX()))));
    w.step(static_cast<int>(std::lround(10.0 / dt)));
    const double up = (w.rootPose("cube").orientation * Vec3::UnitZ()).z();
    const double tilt = std::acos(std::min(1.0, up)) * 180.0 / M_PI;
    std::printf("bottom-heavy cube, step %g s: tilt %.3f deg after 10 s\n", dt, tilt);
    test::printFigure(test::figureName("tilt_deg_%gms", dt * 1000), tilt);
    EXPECT_LT(tilt, 5.0) << dt;
  }
}

// A 1 g sheet of 0.2 x 0.2 m thrown face-on at 100 m/s through air without gravity: its drag
// is stiff (step x rho Cd A v / m = 5.5 at 2 ms, where the explicit step would turn it to
// -454 m/s), so the world treats it implicitly: the speed falls without reversing and
// follows the analytic v0 / (1 + k A v0 t / m) of dv/dt = -k A v^2 / m (k = rho Cd / 2).
// The implicit (secant) step v1 = v0 / (1 + k A v0 dt / m) is exact; once slow enough the
// drag is explicit and first order: 4.1% low after 0.2 s at 2 ms, 0.8% at 0.25 ms.
// Without added mass: its 7.6 g of air would make the sheet 8.6 times heavier, and its drag
// no longer stiff.
TEST(StiffDrag, LightSheetThrownFaceOnSlowsWithoutReversing) {
  auto sheet = parseCreatureModel(R"(<robot name="sheet"><link name="s">
    <inertial><mass value="0.001"/>
      <inertia ixx="3.33e-6" ixy="0" ixz="0" iyy="3.33e-6" iyz="0" izz="6.67e-6"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.0005"/></geometry></collision></link></robot>)");
  const double m = 0.001, v0 = 100.0, seconds = 0.2;
  for (double dt : {0.002, 0.00025}) {
    WorldParams p = test::openSky();
    p.gravity = Vec3::Zero();
    p.air.buoyancy = false;
    p.air.added_mass = false;
    p.step_size = dt;
    World w(p);
    Twist thrown;
    thrown.linear = Vec3(0, 0, v0);
    w.spawn("sheet", sheet, at(0, 0, 0), thrown);
    double last = v0;
    bool monotonic = true;
    const int steps = static_cast<int>(std::lround(seconds / dt));
    for (int i = 0; i < steps; ++i) {
      w.step(1);
      const double v = w.rootTwist("sheet").linear.z();
      monotonic = monotonic && v > 0.0 && v <= last;
      last = v;
    }
    const double ka = 0.5 * p.air.density * p.air.drag_coefficient * 0.2 * 0.2;
    const double expected = v0 / (1.0 + ka * v0 * seconds / m);
    std::printf("sheet thrown at %g m/s, step %g s: %.6f m/s after %g s, analytic %.6f m/s\n", v0,
                dt, last, seconds, expected);
    test::printFigure(test::figureName("speed_%gms", dt * 1000), last);
    test::printFigure(test::figureName("expected_%gms", dt * 1000), expected);
    test::printFigure(test::figureName("monotonic_%gms", dt * 1000), monotonic ? 1 : 0);
    EXPECT_TRUE(monotonic) << dt;
    EXPECT_NEAR(last, expected, (dt > 0.001 ? 0.05 : 0.01) * expected) << dt;
  }
}

}  // namespace
}  // namespace flapsim
