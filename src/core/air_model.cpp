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

void appendBox(AeroSurface& surface, const Vec3& size, const Pose& origin, int nu, int nv) {
  const std::vector<SurfaceCell> cells = boxSurfaceCells(size, origin, nu, nv);
  const int per_face = static_cast<int>(cells.size()) / 6;
  for (int f = 0; f < 6 && per_face > 0; ++f) {
    const int axis = f / 2;
    const double sign = f % 2 == 0 ? 1.0 : -1.0;  // boxSurfaceCells' order
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    SurfaceFace face;
    face.normal = cells[f * per_face].normal;
    for (int k = 0; k < 4; ++k) {
      Vec3 p = Vec3::Zero();
      p[axis] = sign * 0.5 * size[axis];
      p[b] = (k & 1 ? 0.5 : -0.5) * size[b];
      p[c] = (k & 2 ? 0.5 : -0.5) * size[c];
      face.corners[k] = origin.apply(p);
    }
    face.first_cell = static_cast<int>(surface.cells.size()) + f * per_face;
    face.cell_count = per_face;
    surface.faces.push_back(face);
  }
  surface.cells.insert(surface.cells.end(), cells.begin(), cells.end());
  surface.volume += size.prod();
}

Wrench PressureAirModel::bodyWrench(const BodyKinematics& body, const AeroSurface& surface,
                                    const AirParams& air, std::vector<Vec3>* cell_forces) const {
  // Work in the body frame: cell centres and normals are constant there.
  const Eigen::Matrix3d rot = body.orientation.toRotationMatrix();
  const Vec3 v = rot.transpose() * body.linear_velocity;
  const Vec3 w = rot.transpose() * body.angular_velocity;
  const Vec3 wind = rot.transpose() * air.wind;
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  auto cellRange = [&](int first, int count) {
    for (int i = first; i < first + count; ++i) {
      const SurfaceCell& cell = surface.cells[i];
      const Vec3 u = relativeAirVelocity(v, w, cell.centre, wind);
      const Vec3 f =
          pressureForce(u, cell.normal, cell.area, air.density, surface.drag_coefficient);
      if (f.isZero(0.0)) continue;
      force += f;
      torque += cell.centre.cross(f);
      if (cell_forces) (*cell_forces)[i] = rot * f;
    }
  };
  if (surface.faces.empty()) {
    cellRange(0, static_cast<int>(surface.cells.size()));
  } else {
    for (const SurfaceFace& face : surface.faces) {
      // u.n is affine over the face: if no corner advances, no cell does.
      bool advancing = false;
      for (const Vec3& corner : face.corners) {
        advancing = advancing || relativeAirVelocity(v, w, corner, wind).dot(face.normal) > 0.0;
      }
      if (advancing) cellRange(face.first_cell, face.cell_count);
    }
  }
  return Wrench{rot * force, rot * torque};
}

}  // namespace flapsim
