#include "world_air.h"

#include <utility>

#include "bullet_scene.h"
#include "creature_body.h"
#include "flapsim/air_models.h"

namespace flapsim {

AeroSurface linkSurface(const LinkModel& l, const AirParams& air) {
  AeroSurface surface;
  const int nu = l.aero.subdivisions_u > 0 ? l.aero.subdivisions_u : air.subdivisions_u;
  const int nv = l.aero.subdivisions_v > 0 ? l.aero.subdivisions_v : air.subdivisions_v;
  const Pose com_inv{-l.com, Quat::Identity()};
  for (const Box& b : l.boxes) appendBox(surface, b.size, com_inv * b.origin, nu, nv);
  surface.drag_coefficient =
      l.aero.drag_coefficient ? *l.aero.drag_coefficient : air.drag_coefficient;
  return surface;
}

std::vector<AeroBody> makeAeroBodies(const CreatureModel& m, const AirParams& air) {
  std::vector<AeroBody> aero;
  for (size_t k = 0; k < m.links.size(); ++k) {
    const LinkModel& l = m.links[k];
    if (!l.aero.enabled || l.boxes.empty()) continue;
    AeroBody a;
    a.link = static_cast<int>(k);
    a.model = l.aero.model;
    a.surface = linkSurface(l, air);
    a.last.link = a.link;
    aero.push_back(std::move(a));
  }
  return aero;
}

void resurface(std::vector<AeroBody>& aero, const CreatureModel& m, const AirParams& air) {
  for (AeroBody& a : aero) a.surface = linkSurface(m.links[a.link], air);
}

AirStage::AirStage(const std::string& default_model) : default_model_(makeAirModel(default_model)) {
  for (const std::string& name : airModelNames()) named_models_[name] = makeAirModel(name);
}

const AirModel& AirStage::modelOf(const AeroBody& a) const {
  return a.model.empty() ? *default_model_ : *named_models_.at(a.model);
}

void AirStage::apply(CreatureBody& b, const WorldParams& params) const {
  btMultiBody* mb = b.mb.get();
  const AirParams& air = params.air;
  for (AeroBody& a : b.aero) {
    const int k = a.link;
    const BodyKinematics kin = b.frames.kinematics(k);
    Wrench w =
        modelOf(a).bodyWrench(kin, a.surface, air, record_cells_ ? &a.last.cell_forces : nullptr);
    if (air.buoyancy) w.force += buoyancyForce(a.surface.volume, air.density, params.gravity);
    a.last.com = kin.com;
    a.last.wrench = w;
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
