#include "world/fluid_stage.h"

#include "dynamics/bullet_body.h"
#include "dynamics/momentum_balance.h"
#include "fluid/added_mass.h"
#include "fluid/buoyancy.h"
#include "fluid/fluid_law.h"

namespace flapsim {

AirStage::AirStage(const std::string& default_model) {
  setDefaultModel(makeAirModel(default_model));
}

void AirStage::setDefaultModel(AirModelPtr model) { default_model_ = std::move(model); }

namespace {

// Per link, its spatial velocity relative to the fluid at the fixed point `origin` (the root's
// COM at the step's start) and the bias b of its spatial acceleration there: the part that a
// velocity change composed from the root's COM and the joints' rates (the servo stage's, with
// the subspaces of the step's start) leaves out. The root's: [0; -w x v] (the COM moves off
// the fixed point); each child's: its parent's plus v_parent x v_child (the joint's subspace
// turns with the parent: Featherstone's c = v x S qdot).
void accelerationBias(const CreatureModel& m, const LinkFrames& frames, const Vec3& origin,
                      const Vec3& wind, std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& velocity,
                      std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& bias) {
  const size_t n = m.links.size();
  velocity.resize(n);
  bias.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const BodyKinematics kin = frames.kinematics(static_cast<int>(k));
    const Vec3 w = kin.angular_velocity;
    velocity[k] << w, kin.linear_velocity - wind + w.cross(origin - kin.com);
    if (k == 0) {
      bias[0] << Vec3::Zero(), -w.cross(kin.linear_velocity - wind);
      continue;
    }
    const int parent = m.joints[m.links[k].parent_joint].parent_link;
    bias[k] = bias[parent] + crossMotion(velocity[parent], velocity[k]);
  }
}

// The velocity of the creature's centre of mass (its bodies', not the fluid's).
Vec3 centreVelocity(const CreatureModel& m, const LinkFrames& frames) {
  double mass = 0.0;
  Vec3 momentum = Vec3::Zero();
  for (size_t k = 0; k < m.links.size(); ++k) {
    mass += m.links[k].mass;
    momentum += m.links[k].mass * frames.kinematics(static_cast<int>(k)).linear_velocity;
  }
  return mass > 0.0 ? Vec3(momentum / mass) : Vec3::Zero();
}

// Aero body `a`'s implicit drag for this (sub)step: its law's own linearisation
// (AirModel::linearisation) over half the step where its drag is stiff (the trapezoidal rule,
// and still no face-on drag can reverse a cell's normal speed within a step: v1 = v0 - dt k
// v0^2 / (m + dt k v0)), else none; whether it has one.
bool setImplicitDrag(const AirModel& law, AeroBody& a, const BodyKinematics& kin,
                     const AirParams& air, double reach, double step) {
  const bool implicit =
      air.density > 0.0 && law.linearisation() != AirLinearisation::kNone &&
      needsImplicitDrag(a, kin, air, law.forceCoefficient(a.surface, air),
                        dragMass(a, air.density, law.forcesAlongNormals()), reach, step);
  if (implicit) {
    a.drag = 0.5 * step * lawDamping(law, kin, a.surface, air);
    a.drag_zero = false;
  } else if (!a.drag_zero) {
    a.drag.setZero();
    a.drag_zero = true;
  }
  return implicit;
}

}  // namespace

// What aero body `i`'s added mass does to it beyond the servo stage's -A dnu (its plates
// carry added mass): Kirchhoff's velocity products and the bias b of its acceleration,
// -(A b + nu x* A nu) (internal to body and fluid: not in the momentum balance's external
// impulses), and where the plates shed the products into the wake
// (AddedMassProducts::kShed), the products back: the plate then feels -A dnu/dt in
// its own frame; added to `w`, each term in turn. `centre_velocity`: the creature's centre of
// mass's (centreVelocity).
void AirStage::addAddedMass(const CreatureModel& model, BulletBody& body, CreatureFluid& fluid,
                            MomentumBalance& momentum, const AirParams& air, size_t i,
                            const Vec3& centre_velocity, Wrench& w) {
  AeroBody& a = fluid.bodies_[i];
  const BodyKinematics& kin = fluid.kinematics_[i];
  const SpatialFactor& added = fluid.addedMass(i, kin.rotation, air.density);
  if (air.density <= 0.0 || !air.addedMassVelocityProducts()) return;
  const Vec3 origin = fromBt(body.frames().com(0));
  if (fluid.link_bias_.empty()) {
    accelerationBias(model, body.frames(), origin, air.wind, fluid.link_velocity_,
                     fluid.link_bias_);
  }
  // The bias at the link's COM, where the added mass's factor is.
  Vec6 bias = fluid.link_bias_[a.link];
  bias.tail<3>() += bias.head<3>().cross(kin.com - origin);
  w += addedMassVelocityWrench(added, kin.angular_velocity, kin.linear_velocity - air.wind, bias);
  if (!air.shedProducts()) return;
  // They do no work on the plate (nu . (nu x* h) = 0).
  const ShedProducts shed =
      shedProducts(added, kin.angular_velocity, kin.linear_velocity - air.wind);
  a.last.wrench += shed.wrench;
  a.shed = shed.wrench;
  momentum.addShedProducts(kin.com, shed.external(centre_velocity - air.wind));
  w += shed.wrench;
}

void AirStage::apply(const CreatureModel& model, BulletBody& body, CreatureFluid& fluid,
                     MomentumBalance& momentum, const WorldParams& params, double step) const {
  fluid.active_ = false;
  if (!params.air.enabled) return;
  btMultiBody& mb = body.multiBody();
  const AirParams& air = params.air;
  // Every aero body's kinematics, then the pressure law on all those the batch holds at once
  // (not when each cell's force is recorded).
  bool batch = false;
  for (size_t i = 0; i < fluid.bodies_.size(); ++i) {
    body.frames().kinematics(fluid.bodies_[i].link, fluid.kinematics_[i]);
    batch = batch || (fluid.pressure_.holds(i) && batchedPressureLaw(modelOf(fluid.bodies_[i])));
  }
  batch = batch && !record_cells_;
  if (batch) fluid.pressure_.run(fluid.kinematics_, air, fluid.batch_wrench_);
  // Buoyancy is the pressure gradient of the fluid at rest under gravity; a fluid whose
  // velocity changed since the last (sub)step accelerated, and its pressure gradient pushes
  // the displaced volume with it: -rho V (g - dU/dt), the Froude-Krylov force. (The added
  // mass's share, A dU/dt, comes from its momentum, measured relative to the fluid:
  // dynamics/momentum_balance.h.)
  const Vec3 fluid_gravity = params.gravity - fluid.flowAcceleration(air.wind, step);
  fluid.link_bias_.clear();  // this (sub)step's, once a plate needs it
  const Vec3 centre_velocity =
      air.shedProducts() ? centreVelocity(model, body.frames()) : Vec3::Zero();
  for (size_t i = 0; i < fluid.bodies_.size(); ++i) {
    AeroBody& a = fluid.bodies_[i];
    const int k = a.link;
    const BodyKinematics& kin = fluid.kinematics_[i];
    const AirModel& law = modelOf(a);
    Wrench w =
        batch && fluid.pressure_.holds(i) && batchedPressureLaw(law)
            ? fluid.batch_wrench_[i]
            : law.bodyWrench(kin, a.surface, air, record_cells_ ? &a.last.cell_forces : nullptr);
    if (air.buoyancy) w += buoyancyLaw(FluidInput{kin, a.surface, air, fluid_gravity}, nullptr);
    a.last.com = kin.com;
    a.last.wrench = w;
    momentum.addExternal(kin.com, w);
    if (a.has_added_mass) {
      addAddedMass(model, body, fluid, momentum, air, i, centre_velocity, w);
    }
    const bool implicit = setImplicitDrag(law, a, kin, air, body.reach(k), step);
    fluid.active_ = fluid.active_ || implicit || (a.has_added_mass && air.density > 0.0);
    if (record_cells_) {
      a.last.cell_centres.resize(a.surface.cells.size());
      for (size_t c = 0; c < a.surface.cells.size(); ++c) {
        a.last.cell_centres[c] = kin.com + kin.orientation * a.surface.cells[c].centre;
      }
    }
    if (k == 0) {
      mb.addBaseForce(toBt(w.force));
      mb.addBaseTorque(toBt(w.torque));
    } else {
      mb.addLinkForce(k - 1, toBt(w.force));
      mb.addLinkTorque(k - 1, toBt(w.torque));
    }
  }
}

}  // namespace flapsim
