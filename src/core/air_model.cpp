#include "flapsim/air_model.h"

namespace flapsim {

std::vector<SurfaceCell> boxSurfaceCells(const Vec3& size, const Pose& origin, int nu, int nv) {
  std::vector<SurfaceCell> cells;
  if (nu < 1 || nv < 1) return cells;
  cells.reserve(static_cast<size_t>(6 * nu * nv));
  for (int axis = 0; axis < 3; ++axis) {
    const int b = (axis + 1) % 3;
    const int c = (axis + 2) % 3;
    const double cell_area = size[b] * size[c] / (nu * nv);
    for (double sign : {1.0, -1.0}) {
      Vec3 normal = Vec3::Zero();
      normal[axis] = sign;
      for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
          Vec3 p = Vec3::Zero();
          p[axis] = sign * 0.5 * size[axis];
          p[b] = size[b] * ((i + 0.5) / nu - 0.5);
          p[c] = size[c] * ((j + 0.5) / nv - 0.5);
          cells.push_back(SurfaceCell{origin.apply(p), origin.orientation * normal, cell_area});
        }
      }
    }
  }
  return cells;
}

Wrench PressureAirModel::bodyWrench(const BodyKinematics& body, const AeroSurface& surface,
                                    const AirParams& air, std::vector<Vec3>* cell_forces) const {
  Wrench total;
  if (cell_forces) cell_forces->resize(surface.cells.size());
  const Eigen::Matrix3d rot = body.orientation.toRotationMatrix();
  for (size_t i = 0; i < surface.cells.size(); ++i) {
    const SurfaceCell& cell = surface.cells[i];
    const Vec3 r = rot * cell.centre;
    const Vec3 n = rot * cell.normal;
    const Vec3 u = relativeAirVelocity(body.linear_velocity, body.angular_velocity, r, air.wind);
    const Vec3 f = pressureForce(u, n, cell.area, air.density, surface.drag_coefficient);
    total.force += f;
    total.torque += r.cross(f);
    if (cell_forces) (*cell_forces)[i] = f;
  }
  return total;
}

}  // namespace flapsim
