#include "world/transmitted_work.h"

#include "dynamics/bullet_body.h"
#include "dynamics/servo_stage.h"
#include "fluid/creature_fluid.h"

namespace flapsim {

TransmittedWork::TransmittedWork(const CreatureModel& m) : model_(m) {
  const size_t links = m.links.size();
  subtree_.resize(m.joints.size());
  for (size_t j = 0; j < m.joints.size(); ++j) {
    if (!m.joints[j].movable()) continue;
    for (size_t k = 0; k < links; ++k) {
      // Link k is beyond joint j if j's child is on its path to the root.
      for (int x = static_cast<int>(k); x >= 0;) {
        if (x == m.joints[j].child_link) {
          subtree_[j].push_back(static_cast<int>(k));
          break;
        }
        const int parent = m.links[x].parent_joint;
        x = parent < 0 ? -1 : m.joints[parent].parent_link;
      }
    }
  }
  for (Snapshot* s : {&start_, &end_}) {
    s->bodies.resize(links);
    s->joints.resize(m.joints.size());
  }
  metered_.assign(links, 0);
  for (const std::vector<int>& beyond : subtree_) {
    for (int k : beyond) metered_[k] = 1;
  }
  velocity_.assign(links, Vec3::Zero());
  omega_.assign(links, Vec3::Zero());
  impulse_.assign(links, Vec6::Zero());
  start_com_.assign(links, Vec3::Zero());
}

void TransmittedWork::take(BulletBody& body, CreatureFluid& fluid, Snapshot& out) {
  const btMultiBody& mb = body.multiBody();
  const LinkFrames& frames = body.frames();
  Vec3 momentum = Vec3::Zero();
  double mass = 0.0;
  for (size_t k = 0; k < out.bodies.size(); ++k) {
    const int link = static_cast<int>(k);
    const LinkModel& l = model_.links[k];
    const Mat3& to_world = frames.rotation(link);  // the link's velocities are in its frame
    BodyMomentum& b = out.bodies[k];
    b.com = fromBt(frames.com(link));
    velocity_[k] = to_world * fromBt(frames.velocity(link));
    b.linear = l.mass * velocity_[k];
    b.fluid_linear.setZero();
    momentum += b.linear;
    mass += l.mass;
    if (!metered_[k]) continue;
    const Vec3 omega = fromBt(frames.omega(link));
    b.angular = to_world * l.inertia.cwiseProduct(omega);
    omega_[k] = to_world * omega;
  }
  // The bodies' centre of mass: the frame moves as any observer's does; an anchored
  // creature's is its anchor's, the world's.
  out.centre_velocity = mass > 0.0 && !model_.fixed_base ? Vec3(momentum / mass) : Vec3::Zero();
  if (density_ > 0.0) {
    // The tree's frames: the momentum balance updates them, except on an anchored creature,
    // which it leaves alone.
    if (model_.fixed_base) body.world().tree().updateFrames(mb);
    const std::vector<AeroBody>& aero = fluid.bodies();
    for (size_t i = 0; i < aero.size(); ++i) {
      const int k = aero[i].link;
      if (!aero[i].has_added_mass || !metered_[k]) continue;
      // The fluid carried along: the momentum of the plate's velocity relative to the fluid.
      Vec6 v;
      v << omega_[k], velocity_[k] - fluid_velocity_;
      // The tree's rotation, as the momentum balance's (the added mass turned once).
      const Mat3& rotation = body.world().tree().rotations()[k];
      const Vec6 f = factorTimes(fluid.addedMass(i, rotation, density_), v);
      BodyMomentum& b = out.bodies[k];
      b.angular += f.head<3>();
      b.linear += f.tail<3>();
      b.fluid_linear = f.tail<3>();
    }
  }
  for (size_t j = 0; j < model_.joints.size(); ++j) {
    const JointModel& joint = model_.joints[j];
    if (!joint.movable()) continue;
    JointPlace& p = out.joints[j];
    p.position = mb.getJointPos(joint.child_link - 1);
    p.place = body.jointAxis(joint);
  }
}

void TransmittedWork::beginSubStep(BulletBody& body, CreatureFluid& fluid, double density,
                                   const Vec3& fluid_velocity) {
  const bool same_fluid = density == density_ && fluid_velocity == fluid_velocity_;
  density_ = density;
  fluid_velocity_ = fluid_velocity;
  if (valid_ && same_fluid) {
    std::swap(start_, end_);
  } else {
    take(body, fluid, start_);
  }
  valid_ = false;
  known_ = false;
  origin_ = fromBt(body.frames().com(0));
  for (size_t k = 0; k < impulse_.size(); ++k) {
    impulse_[k].setZero();
    start_com_[k] = start_.bodies[k].com;
  }
}

void TransmittedWork::addImpulse(int link, const Vec3& com, const Vec6& impulse) {
  if (!metered_[link]) return;
  Vec6& total = impulse_[link];
  total.head<3>() += impulse.head<3>() + (com - start_com_[link]).cross(impulse.tail<3>());
  total.tail<3>() += impulse.tail<3>();
}

void TransmittedWork::endSubStep(BulletBody& body, CreatureFluid& fluid, const ServoStage& servos,
                                 bool air, const Vec3& gravity, bool constrained, double h) {
  if (air) {
    const std::vector<AeroBody>& aero = fluid.bodies();
    for (size_t i = 0; i < aero.size(); ++i) {
      const AeroBody& a = aero[i];
      const int k = a.link;
      if (!metered_[k]) continue;
      // The explicit wrench held over the (sub)step (about the COM of its start), and the
      // implicit drag's impulse (about the root's COM at the start) moved there.
      const Vec6 drag = servos.dragImpulse(i);
      const Vec3 force = h * a.last.wrench.force + drag.tail<3>();
      impulse_[k].head<3>() +=
          h * (a.last.wrench.torque + (a.last.com - start_com_[k]).cross(a.last.wrench.force)) +
          momentAbout(drag, origin_, start_com_[k]);
      impulse_[k].tail<3>() += force;
    }
  }
  take(body, fluid, end_);
  valid_ = true;
  gravity_ = gravity;
  known_ = !constrained;
}

double TransmittedWork::work(size_t joint, const ServoStage& servos, const btMultiBody& mb,
                             double h) const {
  const JointModel& j = model_.joints[joint];
  const int link = j.child_link - 1;
  const JointPlace &a = start_.joints[joint], &b = end_.joints[joint];
  const Vec3 axis = (a.place.axis + b.place.axis).normalized();
  const double moved = b.position - a.position;
  const double mean_rate = 0.5 * h * (servos.startVelocity(link) + mb.getJointVel(link));
  double transmitted = 0.0, weight = 0.0;  // impulse along the axis; gravity's torque
  const Vec3 point = 0.5 * (a.place.point + b.place.point);
  // Momenta relative to the creature's centre of mass at the start: a step's joint-space
  // straight lines move the bodies by other than step x their end velocities, so that momenta
  // of another frame would make the measure depend on the observer.
  const Vec3 frame = start_.centre_velocity, shift = 0.5 * h * frame;
  for (int k : subtree_[joint]) {
    const BodyMomentum &s = start_.bodies[k], &e = end_.bodies[k];
    const double mass = model_.links[k].mass;
    const Vec6& ext = impulse_[k];
    const Vec3 g = mass * gravity_;
    if (j.type == JointType::kPrismatic) {
      transmitted += axis.dot(e.linear - s.linear - ext.tail<3>());  // the frame cancels
      weight += axis.dot(g);
      continue;
    }
    const Vec3 change = e.angular + (e.com - point - shift).cross(e.linear - mass * frame) -
                        s.angular - (s.com - point + shift).cross(s.linear - mass * frame);
    const Vec3 external = ext.head<3>() + (start_com_[k] - point + shift).cross(ext.tail<3>());
    // About a point at rest in that frame, the fluid's impulse also turns by its drift through
    // the fluid: (U - frame) x P_fluid (zero at rest in the fluid, and in vacuum).
    const Vec3 drift = (0.5 * h) * (fluid_velocity_ - frame).cross(s.fluid_linear + e.fluid_linear);
    transmitted += axis.dot(change - external - drift);
    weight += axis.dot((0.5 * (s.com + e.com) - point).cross(g));
  }
  // Less the joint's spring and (implicit) damping: what is left is the motor's.
  double work = transmitted * mean_rate / h - weight * moved;
  if (servos.stiffness(joint) > 0.0) {
    work += servos.stiffness(joint) * (0.5 * (a.position + b.position) - j.reference) * moved;
  }
  if (servos.implicitSpring(joint) && servos.damping(joint) > 0.0) {
    work += servos.damping(joint) * mb.getJointVel(link) * mean_rate;
  }
  return work;
}

}  // namespace flapsim
