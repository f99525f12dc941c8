// The fluid's implicit part as pure functions (added mass of plates, linearised drag), and
// then in the world: water that stays stable, a plate's initial acceleration with its added
// mass, buoyancy that rights a bottom-heavy body.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "flapsim/fluid_inertia.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

constexpr double kWater = 1000.0;

TEST(AddedMass, PlateFormula) {
  // rho pi c^2 b / 4 with c the shorter edge.
  EXPECT_DOUBLE_EQ(plateAddedMass(1000.0, 0.1, 0.3), 1000.0 * M_PI * 0.01 * 0.3 / 4.0);
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
  EXPECT_NEAR(n.dot(a.bottomRightCorner<3, 3>() * n), expected, 1e-12 * expected);
  const Vec3 in_plane = tilted.orientation * Vec3::UnitX();
  EXPECT_NEAR(in_plane.dot(a.bottomRightCorner<3, 3>() * in_plane), 0.0, 1e-12 * expected);
  std::vector<NormalMass> cube;
  appendPlateAddedMass(cube, Vec3(0.1, 0.1, 0.1), Pose(), 4, 4);
  EXPECT_TRUE(cube.empty());
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
  const Mat6 d = dragDamping(body, surface, air);
  const double k = 0.5 * kWater * 1.15;
  EXPECT_NEAR(d(5, 5), 2.0 * k * 0.06 * 2.0, 1e-9);
  EXPECT_NEAR(d(3, 3), 0.0, 1e-9);  // the edges (0.002 x 0.3) are parallel to the motion
  // Numerically: the pressure model's force changes by -d(5,5) per m/s of normal speed.
  PressureAirModel model;
  BodyKinematics faster = body;
  faster.linear_velocity.z() -= 1e-6;
  const double dfz = model.bodyWrench(faster, surface, air, nullptr).force.z() -
                     model.bodyWrench(body, surface, air, nullptr).force.z();
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
  const Mat6 a = dragDamping(body, grid, air);
  const Mat6 b = dragDamping(body, cells, air);
  ASSERT_GT(b.norm(), 1e-3);
  EXPECT_LT((a - b).norm(), 1e-12 * b.norm());
  EXPECT_LT((a - a.transpose()).norm(), 1e-12 * a.norm());  // symmetric
}

}  // namespace
}  // namespace flapsim
