#include "fluid/added_mass.h"

#include <algorithm>
#include <cmath>

namespace flapsim {

namespace {

// DNV-RP-C205 table A-2, rectangular plates: {c / b, C_A}, c / b falling (b / c = 1, 1.25,
// 1.5, 1.59, 2, 2.5, 3, 4, 5, 6.25, 8, 10, infinity).
constexpr double kPlateTable[][2] = {{1.0, 0.579},        {1.0 / 1.25, 0.642}, {1.0 / 1.5, 0.690},
                                     {1.0 / 1.59, 0.704}, {1.0 / 2.0, 0.757},  {1.0 / 2.5, 0.801},
                                     {1.0 / 3.0, 0.830},  {1.0 / 4.0, 0.871},  {1.0 / 5.0, 0.897},
                                     {1.0 / 6.25, 0.917}, {1.0 / 8.0, 0.934},  {1.0 / 10.0, 0.947},
                                     {0.0, 1.0}};

}  // namespace

double plateAddedMassCoefficient(double chord, double span) {
  const double lo = std::min(chord, span), hi = std::max(chord, span);
  const double r = hi > 0.0 ? lo / hi : 1.0;  // c / b in [0, 1]
  constexpr size_t n = sizeof(kPlateTable) / sizeof(kPlateTable[0]);
  for (size_t i = 1; i < n; ++i) {
    if (r >= kPlateTable[i][0]) {
      const double* a = kPlateTable[i - 1];
      const double* b = kPlateTable[i];
      return b[1] + (a[1] - b[1]) * (r - b[0]) / (a[0] - b[0]);
    }
  }
  return 1.0;
}

double plateAddedMass(double density, double chord, double span) {
  return plateAddedMassCoefficient(chord, span) * density * M_PI * chord * chord * span / 4.0;
}

void appendPlateAddedMass(std::vector<NormalMass>& masses, const Vec3& size, const Pose& origin,
                          int nu, int nv) {
  int thin = 0;
  size.minCoeff(&thin);
  const int b = (thin + 1) % 3, c = (thin + 2) % 3;
  const double chord = std::min(size[b], size[c]), span = std::max(size[b], size[c]);
  if (size[thin] > kPlateThickness * chord || chord <= 0.0) return;
  const double total = plateAddedMass(1.0, chord, span);
  Vec3 normal = Vec3::Zero();
  normal[thin] = 1.0;
  normal = origin.orientation * normal;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      Vec3 p = Vec3::Zero();
      p[b] = ((i + 0.5) / nu - 0.5) * size[b];
      p[c] = ((j + 0.5) / nv - 0.5) * size[c];
      masses.push_back(NormalMass{origin.apply(p), normal, total / (nu * nv)});
    }
  }
}

Mat6 normalInertia(const std::vector<NormalMass>& masses, double scale) {
  Mat6 out = Mat6::Zero();
  for (const NormalMass& m : masses) {
    addNormalWeight(out, m.point.cross(m.normal), m.normal, scale * m.mass);
  }
  return out;
}

Wrench addedMassVelocityWrench(const SpatialFactor& added, const Vec3& omega, const Vec3& velocity,
                               const Vec6& bias) {
  Vec6 nu;
  nu << omega, velocity;
  const Vec6 f = -(crossForce(nu, factorTimes(added, nu)) + factorTimes(added, bias));
  return Wrench{f.tail<3>(), f.head<3>()};
}

ShedProducts shedProducts(const SpatialFactor& added, const Vec3& omega, const Vec3& velocity) {
  Vec6 nu;
  nu << omega, velocity;
  return shedProducts(nu, factorTimes(added, nu));
}

ShedProducts shedProducts(const Vec6& nu, const Vec6& h) {
  const Vec6 products = crossForce(nu, h);
  return ShedProducts{Wrench{products.tail<3>(), products.head<3>()}, h.tail<3>()};
}

Wrench ShedProducts::external(const Vec3& centre_relative_velocity) const {
  return Wrench{wrench.force, wrench.torque - centre_relative_velocity.cross(linear_momentum)};
}

}  // namespace flapsim
