#include "dynamics/momentum_balance.h"

#include "dynamics/bullet_body.h"
#include "fluid/added_mass.h"
#include "fluid/creature_fluid.h"

namespace flapsim {

SystemMomentum MomentumBalance::measure(BulletBody& body, CreatureFluid& fluid, Vec6* shed_end,
                                        double dt) {
  const btMultiBody& mb = body.multiBody();
  TreeDynamics& tree = body.world().tree();
  tree.updateFrames(mb);
  const auto& velocity = tree.velocities(mb);
  const auto& com = tree.coms();
  const auto& inertia = tree.bodyInertias();
  const Vec3 base = fromBt(mb.getBasePos());
  // Sums about the base's COM (systemMomentum()'s, from the tree's spatial inertias): the
  // mass and its first moment, the spatial momentum, and the rotational inertia.
  const size_t n = com.size();
  motions_.resize(n);
  SystemMomentum s;
  Vec3 first_moment = Vec3::Zero();
  Vec6 momentum = Vec6::Zero();
  Mat3 about_base = Mat3::Zero();
  for (size_t k = 0; k < n; ++k) {
    const double mass = model_.links[k].mass;
    s.mass += mass;
    first_moment += mass * com[k];
    momentum.noalias() += inertia[k] * velocity[k];
    about_base += inertia[k].topLeftCorner<3, 3>();
    LinkMotion& b = motions_[k];
    b.com = base + com[k];
    b.angular_velocity = velocity[k].head<3>();
    b.velocity = velocity[k].tail<3>() + b.angular_velocity.cross(com[k]);
  }
  if (s.mass <= 0.0) return s;
  // About the common COM c: the same linear momentum, the moment less c x p, and the
  // inertia less that of the whole mass at c (parallel axes).
  const Vec3 c = first_moment / s.mass;
  s.com = base + c;
  s.linear = momentum.tail<3>();
  s.body_linear = s.linear;
  s.angular = momentum.head<3>() - c.cross(s.linear);
  s.inertia = about_base - s.mass * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
  if (density_ <= 0.0) return s;
  // The shed products at this state, as AirStage::addAddedMass takes them at the start
  // (fluid_stage.cpp): about O where it is at the end, moved with the fluid by U dt, less the
  // creature's share (V - U) x h_linear.
  const Vec3 o = origin_ + dt * fluid_velocity_;
  const Vec3 centre_relative = s.body_linear / s.mass - fluid_velocity_;
  const std::vector<AeroBody>& aero = fluid.bodies();
  for (size_t i = 0; i < aero.size(); ++i) {
    const AeroBody& a = aero[i];
    if (!a.has_added_mass) continue;
    const LinkMotion& b = motions_[a.link];
    // The fluid carried along moves with the plate relative to the fluid at large: its
    // momentum is that of the relative velocity, the same seen from any uniformly moving frame.
    Vec6 v;
    v << b.angular_velocity, b.velocity - fluid_velocity_;
    const Vec6 h =
        addFluidMomentum(s, fluid.addedMass(i, tree.rotations()[a.link], density_), b.com, v);
    if (shed_end == nullptr) continue;
    const ShedProducts end = shedProducts(v, h);
    fluid.holdMeanShedProducts(i, end.wrench, b.com);
    // ShedProducts::external's moment about o, summed in this order (the stored figures' bits).
    shed_end->head<3>() += (b.com - o).cross(end.wrench.force) + end.wrench.torque -
                           centre_relative.cross(end.linear_momentum);
    shed_end->tail<3>() += end.wrench.force;
  }
  return s;
}

void MomentumBalance::begin(BulletBody& body, CreatureFluid& fluid, double added_mass_density,
                            const Vec3& fluid_velocity, AddedMassProducts products) {
  external_force_.setZero();
  external_moment_.setZero();
  shed_start_.setZero();
  drag_impulse_.setZero();
  origin_ = fromBt(body.frames().com(0));
  const bool carried = carried_valid_ && carried_density_ == added_mass_density;
  carried_valid_ = false;
  density_ = added_mass_density;
  fluid_velocity_ = fluid_velocity;
  products_ = products;
  if (model_.fixed_base) return;
  if (carried) {
    start_ = carried_;
    return;
  }
  const SystemMomentum s = measure(body, fluid);
  start_.mass = s.mass;
  start_.com = s.com;
  start_.linear = s.linear;
  start_.angular = s.angular;
}

void MomentumBalance::addExternal(const Vec3& com, const Wrench& wrench) {
  external_force_ += wrench.force;
  external_moment_ += (com - origin_).cross(wrench.force) + wrench.torque;
}

void MomentumBalance::addShedProducts(const Vec3& com, const Wrench& wrench) {
  addExternal(com, wrench);
  shed_start_.head<3>() += (com - origin_).cross(wrench.force) + wrench.torque;
  shed_start_.tail<3>() += wrench.force;
}

void MomentumBalance::end(BulletBody& body, CreatureFluid& fluid, const Vec3& gravity, double dt) {
  carried_valid_ = false;
  if (model_.fixed_base || body.hasContacts() || start_.mass <= 0.0) {
    body.framesAfterStep();
    return;
  }
  // What the momentum must be: the start plus the external impulses (gravity has no moment
  // about the centre of mass). The angular part first about O, the point where the centre of
  // mass was at the start, moving with the fluid (at rest in the fluid's frame, where the
  // impulses' moments about it are all that change it).
  // The shed products' impulse by the trapezoidal rule (addShedProducts): at the end, the
  // state before the correction (Heun's predictor), summed by measure().
  const bool shed = products_ == AddedMassProducts::kShed;
  Vec6 shed_end = Vec6::Zero();
  const SystemMomentum now = measure(body, fluid, shed ? &shed_end : nullptr, dt);
  Vec6 air;
  air << external_moment_, external_force_;
  if (shed) air += 0.5 * (shed_end - shed_start_);
  const Vec3 linear =
      start_.linear + dt * (start_.mass * gravity + air.tail<3>()) + drag_impulse_.tail<3>();
  const Vec3 angular_about_o = start_.angular + dt * momentAbout(air, origin_, start_.com) +
                               momentAbout(drag_impulse_, origin_, start_.com);
  // About the centre of mass at the end, which has moved from O by d = dt (v1 - U) in the
  // fluid's frame: L_c = L_O - d x P', with P' the momentum in that frame, M (v1 - U) + P_f, so
  // L_c = L_O - d x P_f (Kirchhoff's -v x P, the Munk moment of the added mass; only with the
  // velocity products, else L_c = L_O). P_f and v1 are those after the correction: a second
  // pass takes them from the first's.
  const Vec3 fluid_linear = now.linear - now.body_linear;
  RigidCorrection c = momentumCorrection(now, linear, angular_about_o);
  Vec3 angular = angular_about_o;
  if (products_ == AddedMassProducts::kKirchhoff && !now.fluid.isZero(0.0)) {
    for (int pass = 0; pass < 2; ++pass) {
      Vec6 twist;
      twist << c.angular_velocity, c.velocity;
      const Vec3 p_f = fluid_linear + (now.fluid * twist).tail<3>();
      const Vec3 d = dt * (now.body_linear / now.mass + c.velocity - fluid_velocity_);
      angular = angular_about_o - d.cross(p_f);
      c = momentumCorrection(now, linear, angular);
    }
  }
  // The centre of mass moves with the bodies' new momentum.
  const Vec3 body_velocity = now.body_linear / now.mass + c.velocity;
  const Vec3 shift = start_.com + dt * body_velocity - now.com;
  // The same rigid motion on the multibody's base and on the frames, which are those of the
  // measure (its tree's rotations are the sums of forwardKinematics) plus the correction.
  btMultiBody& mb = body.multiBody();
  const Vec3 base = fromBt(mb.getBasePos());
  mb.setBasePos(toBt(base + shift));
  mb.setBaseOmega(mb.getBaseOmega() + toBt(c.angular_velocity));
  mb.setBaseVel(mb.getBaseVel() + toBt(c.velocity + c.angular_velocity.cross(base - now.com)));
  const TreeDynamics& tree = body.world().tree();
  body.setRotations(tree);
  const int bodies = static_cast<int>(motions_.size());
  for (int k = 0; k < bodies; ++k) {
    const LinkMotion& b = motions_[k];
    // Velocities into the link's frame, as Bullet keeps them.
    const Mat3& to_world = tree.rotations()[k];
    const Vec3 w = b.angular_velocity + c.angular_velocity;
    const Vec3 v = b.velocity + c.velocity + c.angular_velocity.cross(b.com - now.com);
    body.setFrame(k, toBt(Vec3(b.com + shift)), toBt(Vec3(to_world.transpose() * w)),
                  toBt(Vec3(to_world.transpose() * v)));
  }
  // The momentum is now the target, about the shifted centre of mass (a translation changes
  // no momentum about the centre): the next step starts from it instead of measuring it again.
  carried_.mass = now.mass;
  carried_.com = now.com + shift;
  carried_.linear = linear;
  carried_.angular = angular;
  carried_valid_ = true;
  carried_density_ = density_;
}

}  // namespace flapsim
