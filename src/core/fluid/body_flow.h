// The air's motion seen from a body, and the per-cell sum the cell-by-cell laws share.
// Private to flapsim_core, for the laws' own files (fluid/pressure.cpp, fluid/quasi_steady.cpp):
// internal to each of them (an unnamed namespace), so that each inlines them into its hot
// loop as when they were one file's.
#pragma once

#include <vector>

#include "flapsim/air_model.h"

namespace flapsim {
namespace {

// The air's motion seen from a body: velocities in the body frame, where cell centres and
// normals are constant.
struct BodyFlow {
  BodyFlow(const BodyKinematics& body, const AirParams& air)
      : rot(body.has_body_frame ? body.rotation : body.orientation.toRotationMatrix()),
        v(body.has_body_frame ? body.body_linear_velocity : rot.transpose() * body.linear_velocity),
        w(body.has_body_frame ? body.body_angular_velocity
                              : rot.transpose() * body.angular_velocity),
        wind(air.wind.isZero(0.0) ? Vec3::Zero() : Vec3(rot.transpose() * air.wind)) {}

  Vec3 at(const Vec3& point) const { return relativeAirVelocity(v, w, point, wind); }
  // u.n is affine over a face: if no corner advances into the air, no cell does.
  bool advances(const SurfaceFace& face) const {
    for (const Vec3& corner : face.corners) {
      if (at(corner).dot(face.normal) > 0.0) return true;
    }
    return false;
  }

  Eigen::Matrix3d rot;
  Vec3 v, w, wind;
};

// Sums per-cell forces of `force(u, cell, span)` over a body, skipping retreating faces.
template <typename CellForce>
Wrench sumCells(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                std::vector<Vec3>* cell_forces, CellForce force) {
  const BodyFlow flow(body, air);
  Vec3 total = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  auto cellRange = [&](int first, int count, const Vec3& span) {
    for (int i = first; i < first + count; ++i) {
      const SurfaceCell& cell = surface.cells[i];
      const Vec3 f = force(flow.at(cell.centre), cell, span);
      if (f.isZero(0.0)) continue;
      total += f;
      torque += cell.centre.cross(f);
      if (cell_forces) (*cell_forces)[i] = flow.rot * f;
    }
  };
  if (surface.faces.empty()) {
    cellRange(0, static_cast<int>(surface.cells.size()), Vec3::Zero());
  } else {
    for (const SurfaceFace& face : surface.faces) {
      if (flow.advances(face)) cellRange(face.first_cell, face.cell_count, face.span);
    }
  }
  return Wrench{flow.rot * total, flow.rot * torque};
}

}  // namespace
}  // namespace flapsim
