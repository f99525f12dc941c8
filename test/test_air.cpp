// The air model as pure functions: invariants on tiny inline inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>

#include "doc_figure.h"
#include "flapsim/air_model.h"
#include "fluid/box_union.h"
#include "fluid/buoyancy.h"
#include "fluid/pressure.h"
#include "fluid/quasi_steady.h"
#include "fluid/surface.h"

namespace flapsim {
namespace {

// Water at density rho, for buoyancy.
AirParams water(double rho) {
  AirParams air = waterParams();
  air.density = rho;
  return air;
}

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

// The k-th of a fixed sequence of tumbling motions: arbitrary orientation, velocity, spin.
BodyKinematics tumbling(int k) {
  BodyKinematics b;
  b.orientation = Quat(Eigen::AngleAxisd(0.3 * k, Vec3(1, k, 2).normalized()));
  b.linear_velocity = Vec3(std::sin(k), std::cos(2 * k), -1.0 + 0.1 * k);
  b.angular_velocity = Vec3(5 * std::cos(k), -3.0 + k, 2 * std::sin(3 * k));
  return b;
}

// `fast` equals the reference wrench `a` to 1e-12 of its size (which must not be zero);
// returns that size.
double expectSameWrench(const Wrench& a, const Wrench& fast, int k) {
  const double scale = a.force.norm() + a.torque.norm();
  EXPECT_GT(scale, 0.0) << k;
  EXPECT_NEAR((a.force - fast.force).norm(), 0.0, 1e-12 * scale) << k;
  EXPECT_NEAR((a.torque - fast.torque).norm(), 0.0, 1e-12 * scale) << k;
  return scale;
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
    const BodyKinematics b = tumbling(k);
    std::vector<Vec3> cells_a, cells_b;
    const Wrench a = model.bodyWrench(b, plain, air, &cells_a);
    const Wrench f = model.bodyWrench(b, faces, air, &cells_b);
    const double scale = expectSameWrench(a, f, k);
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

// ---- surfaces of several boxes: hidden cells, union volume, buoyancy ----------------------

Box box(const Vec3& size, const Vec3& centre, const Quat& q = Quat::Identity()) {
  return Box{size, Pose{centre, q}};
}

// The pressure model's wrench on `surface` in a steady flow `u` (the body's velocity).
Wrench pressureIn(const AeroSurface& surface, const Vec3& u) {
  BodyKinematics k;
  k.linear_velocity = u;
  return PressureAirModel().bodyWrench(k, surface, AirParams(), nullptr);
}

// Two 0.1 x 0.2 half plates flush along an edge are one 0.2 x 0.2 plate to the air: the faces
// where they touch are hidden. Edge-on along x those faces would otherwise double the drag.
TEST(BuildSurface, FlushHalfPlatesFeelTheDragOfOneWholePlate) {
  const Vec3 half(0.1, 0.2, 0.002);
  const std::vector<Box> halves{box(half, Vec3(-0.05, 0, 0)), box(half, Vec3(0.05, 0, 0))};
  const AeroSurface two = buildSurface(halves, 4, 4);
  const AeroSurface one = buildSurface({box(Vec3(0.2, 0.2, 0.002), Vec3::Zero())}, 4, 4);
  // Each half keeps its two 4 x 4 faces and three of its four rims (one row of 4 cells across
  // the 2 mm thickness), losing the rim against the other half.
  EXPECT_EQ(two.cells.size(), 2u * (2u * 16u + 3u * 4u));
  EXPECT_EQ(two.faces.size(), 10u);
  for (const SurfaceFace& f : two.faces) {
    EXPECT_EQ(f.nu * f.nv, f.cell_count);  // untouched faces stay grids
    EXPECT_EQ(std::max(f.nu, f.nv), 4);
  }
  AeroSurface unmasked;  // the old way: every face of every box
  for (const Box& b : halves) appendBox(unmasked, b.size, b.origin, 4, 4);
  for (const Vec3& u : {Vec3(0, 0, -2), Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(1.5, -0.7, -1)}) {
    const Vec3 f1 = pressureIn(one, u).force, f2 = pressureIn(two, u).force;
    EXPECT_NEAR((f2 - f1).norm(), 0.0, 1e-12 * f1.norm()) << u.transpose();
  }
  const double edge_on = pressureIn(one, Vec3(2, 0, 0)).force.norm();
  test::printFigure("face_on_one", pressureIn(one, Vec3(0, 0, -2)).force.norm());
  test::printFigure("face_on_two", pressureIn(two, Vec3(0, 0, -2)).force.norm());
  test::printFigure("edge_on_one", edge_on);
  test::printFigure("edge_on_two", pressureIn(two, Vec3(2, 0, 0)).force.norm());
  test::printFigure("edge_on_unmasked", pressureIn(unmasked, Vec3(2, 0, 0)).force.norm());
  EXPECT_NEAR(pressureIn(unmasked, Vec3(2, 0, 0)).force.norm(), 2.0 * edge_on, 1e-12);
  // The quasi-steady model sees the same single plate, given the same span.
  const AeroSurface two_qs = buildSurface(halves, 4, 4, Vec3::UnitY());
  const AeroSurface one_qs =
      buildSurface({box(Vec3(0.2, 0.2, 0.002), Vec3::Zero())}, 4, 4, Vec3::UnitY());
  QuasiSteadyAirModel qs;
  for (const Vec3& u : {Vec3(2, 0, 0), Vec3(1.5, -0.7, -1)}) {
    BodyKinematics k;
    k.linear_velocity = u;
    const Vec3 f1 = qs.bodyWrench(k, one_qs, AirParams(), nullptr).force;
    const Vec3 f2 = qs.bodyWrench(k, two_qs, AirParams(), nullptr).force;
    EXPECT_NEAR((f2 - f1).norm(), 0.0, 1e-12 * f1.norm()) << u.transpose();
  }
}

// A cube buried half in a plate hides the plate's cells under it; that face's survivors are
// summed cell by cell and give what a plain per-cell sum gives, for any motion.
TEST(BuildSurface, PartlyHiddenFaceSumsEqualThePerCellSum) {
  const AeroSurface s = buildSurface(
      {box(Vec3(0.2, 0.2, 0.01), Vec3::Zero()), box(Vec3(0.1, 0.1, 0.1), Vec3(0.05, 0.05, 0.05))},
      4, 4);
  int masked = 0;
  for (const SurfaceFace& f : s.faces) {
    if (f.nu > 0) continue;
    ++masked;
    EXPECT_LT(f.cell_count, 16);
  }
  EXPECT_EQ(masked, 3);  // the plate's top, the cube's bottom... and the cube's faces it pierces
  AeroSurface plain;
  plain.cells = s.cells;
  plain.drag_coefficient = s.drag_coefficient;
  PressureAirModel model;
  AirParams air;
  air.wind = Vec3(0.3, -0.5, 0.2);
  for (int k = 0; k < 10; ++k) {
    const BodyKinematics b = tumbling(k);
    expectSameWrench(model.bodyWrench(b, plain, air, nullptr), model.bodyWrench(b, s, air, nullptr),
                     k);
  }
}

// Two 0.1 m cubes overlapping by half: 1.5 litres, not 2, centred 0.025 m towards the second.
TEST(UnionOfBoxes, AlignedOverlapIsCountedOnceExactly) {
  const Vec3 cube(0.1, 0.1, 0.1);
  const AeroSurface s = buildSurface({box(cube, Vec3::Zero()), box(cube, Vec3(0.05, 0, 0))}, 2, 2);
  test::printFigure("volume_error", std::abs(s.volume - 1.5e-3));
  test::printFigure("centroid_error", (s.centroid - Vec3(0.025, 0, 0)).norm());
  EXPECT_NEAR(s.volume, 1.5e-3, 1e-15);
  EXPECT_NEAR((s.centroid - Vec3(0.025, 0, 0)).norm(), 0.0, 1e-15);
  const Wrench w =
      buoyancyLaw(FluidInput{BodyKinematics(), s, water(1000.0), Vec3(0, 0, -9.81)}, nullptr);
  EXPECT_NEAR(w.force.z(), 1000.0 * 1.5e-3 * 9.81, 1e-12);
  // A 0.1 x 0.2 x 0.1 box turned 90 degrees about z is axis-aligned too: still exact. It
  // spans x in [0, 0.2] and shares 0.05 x 0.1 x 0.1 with the cube.
  const BoxUnion turned = unionOfBoxes(
      {box(cube, Vec3::Zero()), box(Vec3(0.1, 0.2, 0.1), Vec3(0.1, 0, 0),
                                    Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())))});
  EXPECT_NEAR(turned.volume, 2.5e-3, 1e-15);
  EXPECT_NEAR((turned.centroid - Vec3((2e-3 * 0.1 - 5e-4 * 0.025) / 2.5e-3, 0, 0)).norm(), 0.0,
              1e-15);
}

// A cube and the same cube turned 45 degrees about z share a regular octagonal prism of
// cross-section 2 (sqrt 2 - 1) a^2; raised by half its height, the second also moves the
// centroid up. Reference: that geometry; the tolerance: 4x the integration error measured.
TEST(UnionOfBoxes, TurnedOverlapMatchesTheOctagonWithinSamplingError) {
  const double a = 0.1;
  const Vec3 cube(a, a, a);
  const Quat turn(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()));
  const double octagon = 2.0 * (std::sqrt(2.0) - 1.0) * a * a;
  const BoxUnion same = unionOfBoxes({box(cube, Vec3::Zero()), box(cube, Vec3::Zero(), turn)});
  test::printFigure("volume", same.volume);
  test::printFigure("expected", 2 * a * a * a - octagon * a);
  EXPECT_NEAR(same.volume / (2 * a * a * a - octagon * a), 1.0, 1e-4);  // measured -2.5e-5
  EXPECT_NEAR(same.centroid.norm(), 0.0, 1e-4 * a);
  const BoxUnion raised =
      unionOfBoxes({box(cube, Vec3::Zero()), box(cube, Vec3(0, 0, a / 2), turn)});
  const double overlap = octagon * a / 2;
  const double volume = 2 * a * a * a - overlap;
  const double z = (a * a * a * (a / 2) - overlap * (a / 4)) / volume;
  EXPECT_NEAR(raised.volume / volume, 1.0, 1e-4);  // measured -9e-6
  EXPECT_NEAR(raised.centroid.z() / z, 1.0, 1e-4);
  EXPECT_NEAR(raised.centroid.head<2>().norm(), 0.0, 1e-4 * a);
}

// 120 boxes on a 1 cm lattice, overlapping at random (one group of many), some turned 90
// degrees: the union's volume and centroid equal a count of the lattice's 1 cm cells that some
// box holds. Reference: that count, independent of the sweep.
TEST(UnionOfBoxes, ManyAlignedOverlapsEqualALatticeCount) {
  std::vector<Box> boxes;
  unsigned seed = 12345;
  auto next = [&](int n) {
    seed = seed * 1103515245u + 12345u;
    return static_cast<int>((seed >> 16) % static_cast<unsigned>(n));
  };
  constexpr int kCells = 20;
  std::vector<bool> held(kCells * kCells * kCells, false);
  for (int n = 0; n < 120; ++n) {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = next(kCells - 1);
      hi[a] = std::min(kCells, lo[a] + 1 + next(6));
    }
    for (int x = lo[0]; x < hi[0]; ++x)
      for (int y = lo[1]; y < hi[1]; ++y)
        for (int z = lo[2]; z < hi[2]; ++z) held[(x * kCells + y) * kCells + z] = true;
    const Vec3 size = 0.01 * Vec3(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    const Vec3 centre = 0.005 * Vec3(lo[0] + hi[0], lo[1] + hi[1], lo[2] + hi[2]);
    if (n % 3 == 0) {  // the same box, its x and y edges swapped by a quarter turn about z
      boxes.push_back(box(Vec3(size.y(), size.x(), size.z()), centre,
                          Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()))));
    } else {
      boxes.push_back(box(size, centre));
    }
  }
  double volume = 0.0;
  Vec3 moment = Vec3::Zero();
  for (int x = 0; x < kCells; ++x)
    for (int y = 0; y < kCells; ++y)
      for (int z = 0; z < kCells; ++z) {
        if (!held[(x * kCells + y) * kCells + z]) continue;
        volume += 1e-6;
        moment += 1e-6 * 0.01 * Vec3(x + 0.5, y + 0.5, z + 0.5);
      }
  const BoxUnion u = unionOfBoxes(boxes);
  EXPECT_NEAR(u.volume / volume, 1.0, 1e-12);
  EXPECT_NEAR((u.centroid - moment / volume).norm(), 0.0, 1e-14);
}

// 22 cubes of edge 2a about one centre, turned 0, 4, ..., 84 degrees about z (231 pairs, under
// kMaxTurnedOverlaps). Reference: their cross-section in polar form, the largest of the
// squares' radii a / max(|cos(phi - theta)|, |sin(phi - theta)|) at each angle phi, its
// r^2 / 2 integrated over phi by the midpoint rule on 360,000 angles.
TEST(UnionOfBoxes, ManyTurnedCubesMatchTheirPolarCrossSection) {
  const double a = 0.05, h = 0.1;
  std::vector<Box> turned;
  std::vector<double> angles;
  for (int k = 0; k < 22; ++k) {
    angles.push_back(4 * k * M_PI / 180.0);
    turned.push_back(box(Vec3(2 * a, 2 * a, h), Vec3(0, 0, 0.5),
                         Quat(Eigen::AngleAxisd(angles.back(), Vec3::UnitZ()))));
  }
  EXPECT_EQ(turnedOverlaps(turned), 22u * 21u / 2u);
  constexpr int kAngles = 360000;
  double area = 0.0;
  for (int i = 0; i < kAngles; ++i) {
    const double phi = 2 * M_PI * (i + 0.5) / kAngles;
    double r = 0.0;
    for (const double theta : angles) {
      r = std::max(r,
                   a / std::max(std::abs(std::cos(phi - theta)), std::abs(std::sin(phi - theta))));
    }
    area += 0.5 * r * r * 2 * M_PI / kAngles;
  }
  const BoxUnion u = unionOfBoxes(turned);
  EXPECT_NEAR(u.volume / (area * h), 1.0, 8e-4)  // measured -3.8e-4
      << std::setprecision(9) << u.volume / (area * h) - 1;
  EXPECT_NEAR((u.centroid - Vec3(0, 0, 0.5)).norm(), 0.0, 1e-4 * a);
}

// Buoyancy acts at the centroid: a cube whose COM is h below its centre, tilted by theta,
// feels the torque -rho V g h sin(theta) that turns it back upright.
TEST(BuoyancyWrench, BottomHeavyCubeIsTurnedBackUpright) {
  const double a = 0.1, h = 0.02, rho = 1000.0, g = 9.81;
  const AeroSurface s = buildSurface({box(Vec3(a, a, a), Vec3(0, 0, h))}, 2, 2);
  ASSERT_NEAR((s.centroid - Vec3(0, 0, h)).norm(), 0.0, 1e-15);
  double most = 0.0;  // the largest difference from the torque expected
  for (double theta : {-0.5, -0.1, 0.1, 0.5}) {
    for (int i : {0, 1}) {
      const Vec3 axis = Vec3::Unit(i);
      BodyKinematics k;
      k.orientation = Quat(Eigen::AngleAxisd(theta, axis));
      const Wrench w = buoyancyLaw(FluidInput{k, s, water(rho), Vec3(0, 0, -g)}, nullptr);
      EXPECT_NEAR(w.force.z(), rho * a * a * a * g, 1e-12);
      EXPECT_NEAR(w.torque.dot(axis), -rho * a * a * a * g * h * std::sin(theta), 1e-12);
      EXPECT_LT(w.torque.dot(axis) * theta, 0.0);  // against the tilt
      most =
          std::max(most, std::abs(w.torque.dot(axis) + rho * a * a * a * g * h * std::sin(theta)));
      if (theta == 0.1 && i == 0) test::printFigure("torque_0.1rad", w.torque.dot(axis));
    }
  }
  test::printFigure("largest_difference", most);
}

// ---- quasi-steady span, centre of pressure, rotational lift ------------------------------

Wrench quasiSteadyOn(const AeroSurface& s, const BodyKinematics& k, const AirParams& air) {
  return QuasiSteadyAirModel().bodyWrench(k, s, air, nullptr);
}

// With the span given, a square plate and one 1% longer feel forces within 2% (the 1% of
// area) in any steady flow. With the span taken from the longer edge they did not.
TEST(QuasiSteadySpan, SquareAndNearlySquarePlatesAgreeGivenTheSpan) {
  AirParams air;
  air.centre_of_pressure_shift = air.rotational_lift = false;
  const Vec3 square(0.2, 0.2, 0.002), longer(0.2, 0.202, 0.002);
  const AeroSurface a = buildSurface({box(square, Vec3::Zero())}, 4, 4, Vec3::UnitY());
  const AeroSurface b = buildSurface({box(longer, Vec3::Zero())}, 4, 4, Vec3::UnitY());
  AeroSurface old_a, old_b;
  appendBox(old_a, square, Pose(), 4, 4);
  appendBox(old_b, longer, Pose(), 4, 4);
  double worst_old = 1.0;
  double lowest = 1e300, highest = 0.0;  // the force ratios over the flows
  for (const Vec3& u : {Vec3(0, 0, -2), Vec3(2, 0, -0.5), Vec3(0, 2, -0.2), Vec3(1, 1.5, -0.8)}) {
    BodyKinematics k;
    k.linear_velocity = u;
    const double fa = quasiSteadyOn(a, k, air).force.norm();
    const double fb = quasiSteadyOn(b, k, air).force.norm();
    EXPECT_NEAR(fb / fa, 1.0, 0.02) << u.transpose();
    lowest = std::min(lowest, fb / fa);
    highest = std::max(highest, fb / fa);
    const double oa = quasiSteadyOn(old_a, k, air).force.norm();
    const double ob = quasiSteadyOn(old_b, k, air).force.norm();
    worst_old = std::max(worst_old, std::max(ob / oa, oa / ob));
  }
  test::printFigure("lowest_ratio", lowest);
  test::printFigure("highest_ratio", highest);
  EXPECT_GT(worst_old, 2.0);  // the flows above do tell the two spans apart
}

// A thin plate (chord c = 0.2 along x, span along y) glides forward (+x) and down at angle of
// attack alpha. Its force acts d_cp = c (0.82 alpha / pi + 0.05) behind the leading edge
// (Whitney & Wood 2010): ahead of mid-chord, so about the mid-chord COM the moment is
// -(c/2 - d_cp) F_z about y: nose (+x) up. Backwards, the other edge leads: the sign flips.
TEST(QuasiSteadyCentreOfPressure, GlidingPlatePitchesNoseUpByWhitneyWood) {
  const double c = 0.2, span = 0.3, speed = 3.0;
  const AeroSurface s = buildSurface({box(Vec3(c, span, 1e-9), Vec3::Zero())}, 4, 6, Vec3::UnitY());
  AirParams on, off;
  off.centre_of_pressure_shift = false;
  on.rotational_lift = off.rotational_lift = false;
  const QuasiSteadyCoefficients q;
  double most = 0.0;  // the largest relative error of the moment
  for (double deg : {5.0, 10.0, 20.0, 45.0, 80.0}) {
    const double alpha = deg * M_PI / 180.0;
    for (double dir : {1.0, -1.0}) {
      BodyKinematics k;
      k.linear_velocity = speed * Vec3(dir * std::cos(alpha), 0, -std::sin(alpha));
      const Wrench w = quasiSteadyOn(s, k, on);
      // Lift and drag of the Robofly fits, their vertical part.
      const double fz =
          0.5 * kRho * c * span * speed * speed *
          (liftCoefficient(deg, q) * std::cos(alpha) + dragCoefficient(deg, q) * std::sin(alpha));
      EXPECT_NEAR(w.force.z() / fz, 1.0, 1e-6) << deg;
      const double arm = c / 2 - c * (0.82 * alpha / M_PI + 0.05);
      EXPECT_NEAR(w.torque.y() / (-dir * arm * fz), 1.0, 1e-6) << deg << " dir " << dir;
      most = std::max(most, std::abs(w.torque.y() / (-dir * arm * fz) - 1.0));
      if (deg == 10.0 && dir > 0) test::printFigure("torque_y_10deg", w.torque.y());
      EXPECT_NEAR(quasiSteadyOn(s, k, off).torque.norm(), 0.0, 1e-6 * arm * fz) << deg;
    }
  }
  test::printFigure("largest_relative_error", most);
}

// The same plate at alpha = 10 deg also pitching nose-up at rate q (omega = -q y) gains
// C_rot rho U c^2 q per unit span upwards (Sane & Dickinson 2002), C_rot = pi (0.75 - x0):
// x0 = 0.5 about mid-chord, 0 about the leading edge (where U includes the pitch motion).
// Nose-down (q < 0) it loses as much; pitching in still air about the axis gives none.
TEST(QuasiSteadyRotationalLift, FollowsSaneDickinsonAndIsOddInPitchRate) {
  const double c = 0.2, span = 0.3, speed = 2.0, alpha = 10.0 * M_PI / 180.0;
  AeroSurface s = buildSurface({box(Vec3(c, span, 1e-9), Vec3::Zero())}, 4, 6, Vec3::UnitY());
  AirParams on, off;
  on.centre_of_pressure_shift = off.centre_of_pressure_shift = false;
  off.rotational_lift = false;
  const Vec3 v = speed * Vec3(std::cos(alpha), 0, -std::sin(alpha));
  double most = 0.0;  // the largest relative error of the extra lift
  for (double x0 : {0.5, 0.0}) {
    s.pitch_axis_point = Vec3(c * (0.5 - x0), 0, 0);
    for (double q : {1.0, 2.0, -1.0, -2.0}) {
      BodyKinematics k;
      k.linear_velocity = v;
      k.angular_velocity = Vec3(0, -q, 0);
      const Vec3 extra = quasiSteadyOn(s, k, on).force - quasiSteadyOn(s, k, off).force;
      // The chordwise velocity at the pitch axis: v + omega x (axis point).
      const Vec3 at_axis = v + k.angular_velocity.cross(s.pitch_axis_point);
      const double expected = M_PI * (0.75 - x0) * kRho * at_axis.norm() * c * c * span * q;
      EXPECT_NEAR(extra.z() / expected, 1.0, 1e-9) << x0 << " q " << q;
      most = std::max(most, std::abs(extra.z() / expected - 1.0));
      if (x0 == 0.5 && q == 1.0) test::printFigure("lift_mid_chord_q1", extra.z());
      EXPECT_NEAR(extra.head<2>().norm(), 0.0, 1e-9 * std::abs(expected));
    }
  }
  // Still air: only the faces' 0.5 nm offset from the axis moves through it.
  s.pitch_axis_point = Vec3::Zero();
  BodyKinematics still;
  still.angular_velocity = Vec3(0, 3.0, 0);
  const Vec3 extra = quasiSteadyOn(s, still, on).force - quasiSteadyOn(s, still, off).force;
  test::printFigure("largest_relative_error", most);
  EXPECT_NEAR(extra.norm(), 0.0, 1e-15);
}

}  // namespace
}  // namespace flapsim
