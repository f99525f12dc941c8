#include "fluid/added_mass.h"

#include <algorithm>
#include <cmath>

namespace flapsim {

double plateAddedMass(double density, double chord, double span) {
  return density * M_PI * chord * chord * span / 4.0;
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

}  // namespace flapsim
