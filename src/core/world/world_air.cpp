#include "world/world_air.h"

#include <utility>

#include "dynamics/bullet_scene.h"
#include "dynamics/creature_body.h"
#include "flapsim/air_model.h"
#include "fluid/added_mass.h"
#include "fluid/buoyancy.h"
#include "fluid/pressure.h"
#include "fluid/surface.h"

namespace flapsim {

Mat6 linkAddedMass(const LinkModel& l, const AirParams& air) {
  if (!l.aero.added_mass.value_or(air.added_mass)) return Mat6::Zero();
  const int nu = subdivisionsU(l, air), nv = subdivisionsV(l, air);
  std::vector<NormalMass> masses;
  for (const Box& b : comFrameBoxes(l)) appendPlateAddedMass(masses, b.size, b.origin, nu, nv);
  return normalInertia(masses, 1.0);
}

bool needsImplicitDrag(const AeroBody& a, const BodyKinematics& kin, const AirParams& air,
                       double reach, double step) {
  if (a.mass <= 0.0) return true;
  // Far below the threshold (each speed under half of it, squared: no square root), as
  // most links in air are.
  const double limit =
      kImplicitDragRatio * a.mass / (step * air.density * a.surface.drag_coefficient * a.area);
  const double half = 0.45 * limit;
  if ((kin.linear_velocity - air.wind).squaredNorm() < half * half &&
      kin.angular_velocity.squaredNorm() * reach * reach < half * half) {
    return false;
  }
  const double speed =
      (kin.linear_velocity - air.wind).norm() + kin.angular_velocity.norm() * reach;
  const double rate = air.density * a.surface.drag_coefficient * a.area * speed;
  return step * rate > kImplicitDragRatio * a.mass;
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
  for (const SurfaceCell& c : a.surface.cells) a.area += c.area;
}

}  // namespace

std::vector<AeroBody> makeAeroBodies(const CreatureModel& m, const AirParams& air) {
  std::vector<AeroBody> aero;
  for (size_t k = 0; k < m.links.size(); ++k) {
    const LinkModel& l = m.links[k];
    if (!l.aero.enabled || l.boxes.empty()) continue;
    AeroBody a;
    a.link = static_cast<int>(k);
    a.model = l.aero.model;
    setSurface(a, m, air);
    a.last.link = a.link;
    aero.push_back(std::move(a));
  }
  return aero;
}

void resurface(std::vector<AeroBody>& aero, const CreatureModel& m, const AirParams& air) {
  for (AeroBody& a : aero) setSurface(a, m, air);
}

AirStage::AirStage(const std::string& default_model) : default_model_(makeAirModel(default_model)) {
  for (const std::string& name : airModelNames()) named_models_[name] = makeAirModel(name);
}

const AirModel& AirStage::modelOf(const AeroBody& a) const {
  return a.model.empty() ? *default_model_ : *named_models_.at(a.model);
}

void AirStage::apply(CreatureBody& b, const WorldParams& params, double step) const {
  btMultiBody* mb = b.mb.get();
  const AirParams& air = params.air;
  b.fluid_active = false;
  for (AeroBody& a : b.aero) {
    const int k = a.link;
    Mat3 rotation;
    const BodyKinematics kin = b.frames.kinematics(k, &rotation);
    Wrench w =
        modelOf(a).bodyWrench(kin, a.surface, air, record_cells_ ? &a.last.cell_forces : nullptr);
    if (air.buoyancy) w += buoyancyLaw(FluidInput{kin, a.surface, air, params.gravity}, nullptr);
    a.last.com = kin.com;
    a.last.wrench = w;
    b.addExternal(kin.com, w);
    if (a.has_added_mass) b.turnedAddedMass(a, rotation);
    const bool implicit = air.density > 0.0 && needsImplicitDrag(a, kin, air, b.reach[k], step);
    // Half the step: the trapezoidal rule, and still no face-on drag can reverse a cell's
    // normal speed within a step (v1 = v0 - dt k v0^2 / (m + dt k v0)).
    if (implicit) {
      a.drag = 0.5 * step * pressureDragDamping(FluidInput{kin, a.surface, air});
      a.drag_zero = false;
    } else if (!a.drag_zero) {
      a.drag.setZero();
      a.drag_zero = true;
    }
    b.fluid_active = b.fluid_active || implicit || (a.has_added_mass && air.density > 0.0);
    if (record_cells_) {
      a.last.cell_centres.resize(a.surface.cells.size());
      for (size_t i = 0; i < a.surface.cells.size(); ++i) {
        a.last.cell_centres[i] = kin.com + kin.orientation * a.surface.cells[i].centre;
      }
    }
    if (k == 0) {
      mb->addBaseForce(toBt(w.force));
      mb->addBaseTorque(toBt(w.torque));
    } else {
      mb->addLinkForce(k - 1, toBt(w.force));
      mb->addLinkTorque(k - 1, toBt(w.torque));
    }
  }
}

}  // namespace flapsim
