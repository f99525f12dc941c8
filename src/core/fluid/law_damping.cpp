// The implicit part of a fluid law: its own derivative, or central differences of its kernel.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "dynamics/spatial.h"
#include "fluid/fluid_law.h"

namespace flapsim {

namespace {

// The body's motion with `delta` added to component i of its motion [omega; v] in its own
// axes (the same perturbations, whatever way the body faces).
BodyKinematics perturbed(const BodyKinematics& body, const Mat3& to_world, int i, double delta) {
  BodyKinematics b = body;
  const Vec3 along = delta * to_world.col(i % 3);
  if (i < 3) {
    b.angular_velocity += along;
  } else {
    b.linear_velocity += along;
  }
  if (b.has_body_frame) {
    b.body_angular_velocity = b.rotation.transpose() * b.angular_velocity;
    b.body_linear_velocity = b.rotation.transpose() * b.linear_velocity;
  }
  return b;
}

}  // namespace

AirDamping finiteDifferenceDamping(const AirModel& model, const BodyKinematics& body,
                                   const AeroSurface& surface, const AirParams& air) {
  double reach = 0.0;
  for (const SurfaceCell& c : surface.cells) reach = std::max(reach, c.centre.norm());
  const double speed =
      (body.linear_velocity - air.wind).norm() + body.angular_velocity.norm() * reach;
  // Relative steps of about the cube root of the rounding (central differences), and a floor
  // of 1e-6 m/s for a body at rest in the air.
  const double dv = 1e-5 * std::max(speed, 0.1);
  const double dw = dv / std::max(reach, 1e-3);
  const Mat3 to_world = body.has_body_frame ? body.rotation : body.orientation.toRotationMatrix();
  const Mat3 to_body = to_world.transpose();
  // In the body's axes: a body that faces another way gets the same matrix, turned.
  AirDamping d;
  for (int i = 0; i < 6; ++i) {
    const double h = i < 3 ? dw : dv;
    const Wrench plus = model.bodyWrench(perturbed(body, to_world, i, h), surface, air, nullptr);
    const Wrench minus = model.bodyWrench(perturbed(body, to_world, i, -h), surface, air, nullptr);
    d.block<3, 1>(0, i) = -to_body * (plus.torque - minus.torque) / (2.0 * h);
    d.block<3, 1>(3, i) = -to_body * (plus.force - minus.force) / (2.0 * h);
  }
  const AirDamping symmetric = 0.5 * (d + d.transpose());
  Eigen::SelfAdjointEigenSolver<AirDamping> eigen(symmetric);
  const Eigen::Matrix<double, 6, 1> kept = eigen.eigenvalues().cwiseMax(0.0);
  const AirDamping body_axes =
      eigen.eigenvectors() * kept.asDiagonal() * eigen.eigenvectors().transpose();
  AirDamping turn = AirDamping::Zero();
  turn.topLeftCorner<3, 3>() = to_world;
  turn.bottomRightCorner<3, 3>() = to_world;
  return turn * body_axes * turn.transpose();
}

AirDamping lawDamping(const AirModel& model, const BodyKinematics& body, const AeroSurface& surface,
                      const AirParams& air) {
  switch (model.linearisation()) {
    case AirLinearisation::kOwn:
      return model.dragDamping(body, surface, air);
    case AirLinearisation::kFiniteDifference:
      return finiteDifferenceDamping(model, body, surface, air);
    case AirLinearisation::kNone:
      break;
  }
  return AirDamping::Zero();
}

}  // namespace flapsim
