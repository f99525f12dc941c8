// The pressure sweep (paper Fig. 14-15) and the quasi-steady blade-element model.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "flapsim/air_model.h"
#include "flapsim/sweep.h"
#include "fluid/quasi_steady.h"

namespace flapsim {
namespace {

// pressure by inclination for one model / Cd / grid
std::map<double, SweepRow> curve(const std::vector<SweepRow>& rows, const std::string& model,
                                 double cd, int grid) {
  std::map<double, SweepRow> out;
  for (const auto& r : rows) {
    if (r.model == model && r.drag_coefficient == cd && r.grid == grid) out[r.inclination_deg] = r;
  }
  return out;
}

TEST(Sweep, ThirteenInclinationsPerCurve) {
  const auto rows = pressureSweep(SweepParams());
  EXPECT_EQ(rows.size(), 13u * 3u);  // pressure at Cd 2.0 and 1.15, quasi-steady
  EXPECT_EQ(curve(rows, "pressure", 2.0, 4).size(), 13u);
  EXPECT_EQ(curve(rows, "quasi_steady", 0.0, 4).size(), 13u);
}

TEST(Sweep, SymmetricZeroEdgeOnMaximalFaceOn) {
  const auto rows = pressureSweep(SweepParams());
  for (const auto& key :
       {std::make_pair(std::string("pressure"), 2.0), std::make_pair(std::string("pressure"), 1.15),
        std::make_pair(std::string("quasi_steady"), 0.0)}) {
    auto c = curve(rows, key.first, key.second, 4);
    for (double a = 0; a <= 90; a += 15) {
      EXPECT_NEAR(c[a].pressure, c[180 - a].pressure, 1e-9 * c[90].pressure) << key.first << a;
      EXPECT_NEAR(c[a].lift, -c[180 - a].lift, 1e-9 * c[90].normal_force) << key.first << a;
    }
    EXPECT_NEAR(c[0].pressure, 0.0, 1e-12) << key.first;
    EXPECT_NEAR(c[180].pressure, 0.0, 1e-12) << key.first;
    for (const auto& kv : c) {
      if (kv.first != 90.0) {
        EXPECT_LT(kv.second.pressure, c[90].pressure) << key.first << kv.first;
      }
    }
  }
}

TEST(Sweep, PressureModelFaceOnValueAndScaling) {
  SweepParams p;
  p.models = {"pressure"};
  p.grids = {1, 8};
  const auto rows = pressureSweep(p);
  auto cd2 = curve(rows, "pressure", 2.0, 1), cd115 = curve(rows, "pressure", 1.15, 1);
  EXPECT_NEAR(cd2[90].pressure, 0.5 * 1.204 * 2.0 * 100.0, 1e-9);
  auto fine = curve(rows, "pressure", 2.0, 8);
  for (double a = 15; a < 180; a += 15) {
    EXPECT_NEAR(cd2[a].pressure / cd115[a].pressure, 2.0 / 1.15, 1e-9) << a;
    // Dynamic pressure on the projected area: 1/2 rho Cd U^2 sin(a).
    EXPECT_NEAR(cd2[a].pressure, 120.4 * std::sin(a * M_PI / 180), 1e-9) << a;
    EXPECT_NEAR(fine[a].pressure, cd2[a].pressure, 1e-9) << "uniform flow: grid-free, " << a;
  }
  p.speed = 20.0;
  auto fast = curve(pressureSweep(p), "pressure", 2.0, 1);
  for (double a = 15; a < 180; a += 15) EXPECT_NEAR(fast[a].pressure / cd2[a].pressure, 4.0, 1e-9);
}

TEST(Sweep, RejectsUnknownModels) {
  SweepParams p;
  p.models = {"navier_stokes"};
  EXPECT_THROW(pressureSweep(p), InputError);
}

TEST(QuasiSteady, RoboflyCoefficients) {
  QuasiSteadyCoefficients c;
  EXPECT_NEAR(liftCoefficient(0.0, c), 0.225 + 1.58 * std::sin(-7.20 * M_PI / 180), 1e-12);
  EXPECT_NEAR(liftCoefficient(45.0, c), 0.225 + 1.58 * std::sin((2.13 * 45 - 7.20) * M_PI / 180),
              1e-12);
  EXPECT_NEAR(dragCoefficient(90.0, c), 1.92 - 1.55 * std::cos((2.04 * 90 - 9.82) * M_PI / 180),
              1e-12);
  EXPECT_GT(dragCoefficient(90.0, c), 3.4);  // face-on
  EXPECT_LT(dragCoefficient(0.0, c), 0.4);   // edge-on
}

TEST(QuasiSteady, ForceSplitsIntoDragAndLift) {
  QuasiSteadyCoefficients c;
  const Vec3 span = Vec3::UnitY();
  const double a = 30.0 * M_PI / 180;
  const Vec3 n(-std::sin(a), 0, -std::cos(a));  // lower face, nose up by 30 deg
  const Vec3 u(-5.0, 0, 0);                     // flying towards -x
  const Vec3 f = quasiSteadyForce(u, n, span, 0.01, 1.2, c);
  const double q = 0.5 * 1.2 * 0.01 * 25.0;
  EXPECT_NEAR(f.x(), q * dragCoefficient(30.0, c), 1e-12);  // against the motion
  EXPECT_NEAR(f.z(), q * liftCoefficient(30.0, c), 1e-12);  // up
  EXPECT_NEAR(f.y(), 0.0, 1e-15);
  // A spanwise velocity does not change a blade element's force.
  EXPECT_TRUE(quasiSteadyForce(u + Vec3(0, 3.0, 0), n, span, 0.01, 1.2, c).isApprox(f, 1e-12));
  // A retreating face gets nothing.
  EXPECT_EQ(quasiSteadyForce(-u, n, span, 0.01, 1.2, c), Vec3::Zero());
}

}  // namespace
}  // namespace flapsim
