// The air model as pure functions: invariants on tiny inline inputs.
#include <gtest/gtest.h>

#include <cmath>

#include "flapsim/air_model.h"

namespace flapsim {
namespace {

constexpr double kRho = 1.204;
constexpr double kCd = 1.15;

TEST(BoxCells, CountAreaAndOutwardNormals) {
  const Vec3 size(0.3, 0.2, 0.01);
  auto cells = boxSurfaceCells(size, Pose(), 3, 5);
  ASSERT_EQ(cells.size(), 6u * 3u * 5u);
  double area = 0.0;
  for (const auto& c : cells) {
    area += c.area;
    EXPECT_NEAR(c.normal.norm(), 1.0, 1e-15);
    EXPECT_GT(c.centre.dot(c.normal), 0.0);  // outward
  }
  EXPECT_NEAR(area, 2.0 * (0.3 * 0.2 + 0.2 * 0.01 + 0.01 * 0.3), 1e-15);
}

TEST(BoxCells, FollowTheBoxPose) {
  Pose origin = poseFromXyzRpy(Vec3(1, 2, 3), Vec3(0, 0, M_PI / 2));
  auto cells = boxSurfaceCells(Vec3(2, 1, 1), origin, 1, 1);
  // The +x face of the box, rotated 90 deg about z, faces +y and sits 1 m from the centre.
  EXPECT_TRUE(cells[0].normal.isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE(cells[0].centre.isApprox(Vec3(1, 3, 3), 1e-12));
}

TEST(PressureForce, ZeroAtRestAndOnRetreatingFaces) {
  const Vec3 n(0, 0, -1);
  EXPECT_EQ(pressureForce(Vec3::Zero(), n, 0.1, kRho, kCd), Vec3::Zero());
  EXPECT_EQ(pressureForce(Vec3(0, 0, 2), n, 0.1, kRho, kCd), Vec3::Zero());  // face moves away
  EXPECT_EQ(pressureForce(Vec3(3, 0, 0), n, 0.1, kRho, kCd), Vec3::Zero());  // edge-on
}

TEST(PressureForce, FaceOnValueOpposesMotion) {
  const Vec3 u(0, 0, -2.0);  // moving down, bottom face advances
  const Vec3 f = pressureForce(u, Vec3(0, 0, -1), 0.04, kRho, kCd);
  EXPECT_NEAR(f.z(), 0.5 * kRho * kCd * 0.04 * 4.0, 1e-15);
  EXPECT_LT(f.dot(u), 0.0);
}

TEST(PressureForce, ScalesWithSpeedSquaredAndArea) {
  const Vec3 n = Vec3(1, 0, -1).normalized();
  const Vec3 u(0.3, 0.1, -1.0);
  const Vec3 f1 = pressureForce(u, n, 0.01, kRho, kCd);
  EXPECT_TRUE(pressureForce(2.0 * u, n, 0.01, kRho, kCd).isApprox(4.0 * f1, 1e-14));
  EXPECT_TRUE(pressureForce(u, n, 0.03, kRho, kCd).isApprox(3.0 * f1, 1e-14));
  EXPECT_TRUE(pressureForce(u, n, 0.01, 2 * kRho, kCd).isApprox(2.0 * f1, 1e-14));
}

// Paper eq. 6-7: a plate tilted by phi and falling at speed v feels F_d cos(phi) along its
// normal, whose horizontal part is F_d cos(phi) sin(phi).
TEST(PressureForce, TiltedPlateMatchesEquations6And7) {
  const double v = 1.5, area = 0.04;
  const double fd = 0.5 * kRho * kCd * area * v * v;
  for (double deg : {10.0, 20.0, 30.0, 45.0, 60.0}) {
    const double phi = deg * M_PI / 180.0;
    const Vec3 bottom(-std::sin(phi), 0.0, -std::cos(phi));  // plate pitched by phi about +y
    const Vec3 f = pressureForce(Vec3(0, 0, -v), bottom, area, kRho, kCd);
    EXPECT_NEAR(f.norm(), fd * std::cos(phi), 1e-14) << deg;
    EXPECT_NEAR(f.x(), fd * std::cos(phi) * std::sin(phi), 1e-14) << deg;
    EXPECT_NEAR(f.z(), fd * std::cos(phi) * std::cos(phi), 1e-14) << deg;
  }
}

TEST(Buoyancy, RhoVgAgainstGravity) {
  const Vec3 f = buoyancyForce(0.002, 1000.0, Vec3(0, 0, -9.81));
  EXPECT_NEAR(f.z(), 19.62, 1e-12);
  EXPECT_EQ(f.x(), 0.0);
}

AeroSurface plateSurface(double lx, double ly, int nu, int nv) {
  AeroSurface s;
  s.cells = boxSurfaceCells(Vec3(lx, ly, 0.002), Pose(), nu, nv);
  s.drag_coefficient = kCd;
  return s;
}

// The world's surfaces (appendBox: faces on regular grids, summed per face) give the forces
// of the plain per-cell sum, for arbitrary motion, wind and box pose.
TEST(PressureAirModel, FaceGridSumsEqualThePerCellSum) {
  PressureAirModel model;
  const Pose origin = poseFromXyzRpy(Vec3(0.01, 0.1, -0.02), Vec3(0.2, -0.4, 1.0));
  AeroSurface plain, faces;
  plain.cells = boxSurfaceCells(Vec3(0.2, 0.35, 0.01), origin, 3, 5);
  appendBox(faces, Vec3(0.2, 0.35, 0.01), origin, 3, 5);
  ASSERT_EQ(faces.cells.size(), plain.cells.size());
  EXPECT_NEAR(faces.volume, 0.2 * 0.35 * 0.01, 1e-15);
  AirParams air;
  air.wind = Vec3(1.0, -0.5, 0.2);
  for (int k = 0; k < 20; ++k) {
    BodyKinematics b;
    b.orientation = Quat(Eigen::AngleAxisd(0.3 * k, Vec3(1, k, 2).normalized()));
    b.linear_velocity = Vec3(std::sin(k), std::cos(2 * k), -1.0 + 0.1 * k);
    b.angular_velocity = Vec3(5 * std::cos(k), -3.0 + k, 2 * std::sin(3 * k));
    std::vector<Vec3> cells_a, cells_b;
    const Wrench a = model.bodyWrench(b, plain, air, &cells_a);
    const Wrench f = model.bodyWrench(b, faces, air, &cells_b);
    const double scale = a.force.norm() + a.torque.norm();
    ASSERT_GT(scale, 0.0);
    EXPECT_NEAR((a.force - f.force).norm(), 0.0, 1e-12 * scale) << k;
    EXPECT_NEAR((a.torque - f.torque).norm(), 0.0, 1e-12 * scale) << k;
    for (size_t i = 0; i < cells_a.size(); ++i) {
      EXPECT_NEAR((cells_a[i] - cells_b[i]).norm(), 0.0, 1e-12 * scale) << k << " cell " << i;
    }
  }
}

TEST(PressureAirModel, StillAirAtRestGivesNothing) {
  PressureAirModel model;
  Wrench w = model.bodyWrench(BodyKinematics(), plateSurface(0.2, 0.2, 4, 4), AirParams(), nullptr);
  EXPECT_EQ(w.force, Vec3::Zero());
  EXPECT_EQ(w.torque, Vec3::Zero());
}

TEST(PressureAirModel, WindIsRelativeMotion) {
  PressureAirModel model;
  AeroSurface s = plateSurface(0.2, 0.1, 3, 2);
  BodyKinematics moving;
  moving.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  moving.linear_velocity = Vec3(0.5, -1.0, -2.0);
  moving.angular_velocity = Vec3(1.0, 0.2, 0.0);
  BodyKinematics still = moving;
  still.linear_velocity = Vec3::Zero();
  AirParams wind;
  wind.wind = -moving.linear_velocity;
  Wrench a = model.bodyWrench(moving, s, AirParams(), nullptr);
  Wrench b = model.bodyWrench(still, s, wind, nullptr);
  EXPECT_TRUE(a.force.isApprox(b.force, 1e-12));
  EXPECT_TRUE(a.torque.isApprox(b.torque, 1e-12));
  EXPECT_GT(a.force.norm(), 0.0);
}

TEST(PressureAirModel, FlatTranslationHasNoTorqueAndTotalsFaceOnDrag) {
  PressureAirModel model;
  BodyKinematics k;
  k.linear_velocity = Vec3(0, 0, -2.0);
  Wrench w = model.bodyWrench(k, plateSurface(0.2, 0.2, 4, 4), AirParams(), nullptr);
  EXPECT_NEAR(w.force.z(), 0.5 * kRho * kCd * 0.04 * 4.0, 1e-12);
  EXPECT_NEAR(w.force.x(), 0.0, 1e-15);
  EXPECT_NEAR(w.torque.norm(), 0.0, 1e-15);
}

// Sub-surfaces matter: a plate spinning about one edge feels more pressure at its far end.
TEST(PressureAirModel, SpinningPlateFeelsMoreAtTheTip) {
  PressureAirModel model;
  const double span = 0.3;
  AeroSurface s;
  // Infinitely thin, so that each cell's lever arm is exactly its distance along the span.
  s.cells = boxSurfaceCells(Vec3(0.1, span, 1e-12),
                            poseFromXyzRpy(Vec3(0, span / 2, 0), Vec3::Zero()), 1, 6);
  s.drag_coefficient = kCd;
  BodyKinematics k;
  k.angular_velocity = Vec3(-10.0, 0, 0);  // tip (at +y) moves down
  std::vector<Vec3> cells;
  Wrench w = model.bodyWrench(k, s, AirParams(), &cells);
  // Bottom face cells, ordered root to tip: forces up, growing like r^2.
  std::vector<double> fz;
  for (size_t i = 0; i < s.cells.size(); ++i) {
    if (s.cells[i].normal.z() < -0.5) fz.push_back(cells[i].z());
  }
  ASSERT_EQ(fz.size(), 6u);
  for (size_t i = 1; i < fz.size(); ++i) EXPECT_GT(fz[i], fz[i - 1]);
  const double r0 = span / 12, r5 = 11 * span / 12;
  EXPECT_NEAR(fz[5] / fz[0], (r5 * r5) / (r0 * r0), 1e-6);
  // Total: 1/2 rho Cd chord w^2 sum(r_i^2 dr), and a torque that opposes the spin.
  double expected = 0.0;
  for (int i = 0; i < 6; ++i) {
    const double r = (i + 0.5) * span / 6;
    expected += 0.5 * kRho * kCd * (0.1 * span / 6) * 100.0 * r * r;
  }
  EXPECT_NEAR(w.force.z(), expected, 1e-9 * expected);
  EXPECT_GT(w.torque.x(), 0.0);
}

}  // namespace
}  // namespace flapsim
