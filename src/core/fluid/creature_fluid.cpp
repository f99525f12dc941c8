#include "fluid/creature_fluid.h"

#include <utility>

#include "flapsim/air_model.h"
#include "fluid/added_mass.h"
#include "fluid/surface.h"

namespace flapsim {

Mat6 linkAddedMass(const LinkModel& l, const AirParams& air) {
  if (!l.aero.added_mass.value_or(air.added_mass)) return Mat6::Zero();
  const int nu = subdivisionsU(l, air), nv = subdivisionsV(l, air);
  std::vector<NormalMass> masses;
  for (const Box& b : comFrameBoxes(l)) appendPlateAddedMass(masses, b.size, b.origin, nu, nv);
  return normalInertia(masses, 1.0);
}

double dragMass(AeroBody& a, double density, bool along_normals) {
  if (a.drag_mass_density == density && a.drag_mass_normals == along_normals) return a.drag_mass;
  a.drag_mass = a.mass;
  if (along_normals && a.has_added_mass && density > 0.0 && a.mass > 0.0) {
    const Mat3 inverse =
        (a.mass * Mat3::Identity() + density * a.added_mass.bottomRightCorner<3, 3>()).inverse();
    const double per_mass = (inverse * a.normal_area).trace();  // sum of area n^T M^-1 n
    if (per_mass > 0.0) a.drag_mass = a.area / per_mass;
  }
  a.drag_mass_density = density;
  a.drag_mass_normals = along_normals;
  return a.drag_mass;
}

bool needsImplicitDrag(const AeroBody& a, const BodyKinematics& kin, const AirParams& air,
                       double coefficient, double mass, double reach, double step) {
  if (mass <= 0.0) return true;
  // Far below the threshold (each speed under half of it, squared: no square root), as
  // most links in air are.
  const double limit = kImplicitDragRatio * mass / (step * air.density * coefficient * a.area);
  const double half = 0.45 * limit;
  if ((kin.linear_velocity - air.wind).squaredNorm() < half * half &&
      kin.angular_velocity.squaredNorm() * reach * reach < half * half) {
    return false;
  }
  const double speed =
      (kin.linear_velocity - air.wind).norm() + kin.angular_velocity.norm() * reach;
  const double rate = air.density * coefficient * a.area * speed;
  return step * rate > kImplicitDragRatio * mass;
}

namespace {

void setSurface(AeroBody& a, const CreatureModel& m, const AirParams& air) {
  a.surface = linkAeroSurface(m, a.link, air);
  a.added_mass = linkAddedMass(m.links[a.link], air);
  a.added_factor = factorSpatial(a.added_mass);
  a.has_added_mass = !a.added_mass.isZero(0.0);
  a.added = SpatialFactor();  // it may have had some before
  a.added_valid = false;
  a.mass = m.links[a.link].mass;
  a.area = 0.0;
  a.normal_area.setZero();
  for (const SurfaceCell& c : a.surface.cells) {
    a.area += c.area;
    a.normal_area += c.area * c.normal * c.normal.transpose();
  }
  a.drag_mass_density = -1.0;  // dragMass's answer is for the old surface
}

}  // namespace

CreatureFluid::CreatureFluid(const CreatureModel& m, const AirParams& air) {
  for (size_t k = 0; k < m.links.size(); ++k) {
    const LinkModel& l = m.links[k];
    if (!l.aero.enabled || !l.hasShapes()) continue;
    AeroBody a;
    a.link = static_cast<int>(k);
    a.model = l.aero.model;
    if (!a.model.empty()) a.own_model = makeAirModel(a.model);  // checked by the model's parser
    setSurface(a, m, air);
    a.last.link = a.link;
    bodies_.push_back(std::move(a));
  }
  buildBatch();
}

Vec3 CreatureFluid::flowAcceleration(const Vec3& velocity, double step) {
  const Vec3 change = flow_known_ ? Vec3(velocity - flow_) : Vec3::Zero();
  flow_ = velocity;
  flow_known_ = true;
  return change / step;
}

void CreatureFluid::resurface(const CreatureModel& m, const AirParams& air, bool geometry_changed) {
  for (AeroBody& a : bodies_) {
    const std::optional<double>& own = m.links[a.link].aero.drag_coefficient;
    if (geometry_changed) {
      setSurface(a, m, air);
    } else {
      a.surface.drag_coefficient = own ? *own : air.drag_coefficient;
    }
  }
  buildBatch();
}

void CreatureFluid::buildBatch() {
  std::vector<const AeroSurface*> surfaces;
  for (const AeroBody& a : bodies_) surfaces.push_back(&a.surface);
  pressure_.build(surfaces);
  kinematics_.resize(bodies_.size());
}

const SpatialFactor& CreatureFluid::addedMass(size_t i, const Mat3& rotation, double density) {
  AeroBody& a = bodies_[i];
  if (!a.added_valid || a.added_density != density || a.added_rotation != rotation) {
    if (density <= 0.0 || !a.has_added_mass) {
      a.added.any = false;
    } else {
      turnFactor(a.added_factor, rotation, density, a.added);
    }
    a.added_rotation = rotation;
    a.added_density = density;
    a.added_valid = true;
  }
  return a.added;
}

void CreatureFluid::holdMeanShedProducts(size_t i, const Wrench& end, const Vec3& end_com) {
  AeroBody& a = bodies_[i];
  const Vec3 torque = end.torque + (end_com - a.last.com).cross(end.force);
  a.last.wrench.force += 0.5 * (end.force - a.shed.force);
  a.last.wrench.torque += 0.5 * (torque - a.shed.torque);
}

}  // namespace flapsim
