#include "world/energy_meter.h"

#include "dynamics/bullet_body.h"
#include "dynamics/servo_stage.h"
#include "fluid/creature_fluid.h"

namespace flapsim {

void EnergyMeter::beginSubStep(const CreatureModel& m, const BulletBody& body) {
  origin_ = fromBt(body.frames().com(0));
  axes_.resize(m.joints.size());
  for (size_t ji = 0; ji < m.joints.size(); ++ji) {
    if (m.joints[ji].movable()) axes_[ji] = body.jointAxis(m.joints[ji]);
  }
}

void EnergyMeter::endVelocity(const CreatureModel& m, const btMultiBody& mb,
                              const BodyKinematics& root, int link, const Vec3& point, Vec3& linear,
                              Vec3& angular) const {
  angular = root.angular_velocity;
  linear = root.linear_velocity + angular.cross(point - origin_);
  for (int k = link; k > 0;) {
    const int ji = m.links[k].parent_joint;
    const JointModel& j = m.joints[ji];
    if (j.movable()) {
      const JointAxis& a = axes_[ji];
      const double rate = mb.getJointVel(j.child_link - 1);
      if (j.type == JointType::kPrismatic) {
        linear += rate * a.axis;
      } else {
        angular += rate * a.axis;
        linear += rate * a.axis.cross(point - a.point);
      }
    }
    k = j.parent_link;
  }
}

void EnergyMeter::endSubStep(const CreatureModel& m, const std::vector<JointDrive>& drives,
                             const BulletBody& body, const CreatureFluid& fluid,
                             const ServoStage& servos, bool air, const Vec3& wind, double h) {
  const btMultiBody& mb = body.multiBody();
  if (air) {
    const std::vector<AeroBody>& aero = fluid.bodies();
    const BodyKinematics root = body.frames().kinematics(0);
    for (size_t i = 0; i < aero.size(); ++i) {
      const BodyKinematics& start = fluid.kinematics()[i];
      Vec3 end_linear, end_angular;
      endVelocity(m, mb, root, aero[i].link, start.com, end_linear, end_angular);
      // The impulse over the (sub)step about the link's COM at the start: the explicit wrench
      // held over it, and the implicit drag's (about the root COM) moved there.
      const Vec6 drag = servos.dragImpulse(i);
      const Vec3 force = h * aero[i].last.wrench.force + drag.tail<3>();
      const Vec3 moment = h * aero[i].last.wrench.torque + momentAbout(drag, origin_, start.com);
      const Vec3 v = 0.5 * (start.linear_velocity + end_linear) - wind;
      const Vec3 w = 0.5 * (start.angular_velocity + end_angular);
      air_work_ += force.dot(v) + moment.dot(w);
    }
  }
  for (size_t ji = 0; ji < m.joints.size(); ++ji) {
    // Explicit damping acts on passive joints only (world/joint_drives.h), at the start's
    // velocity; an implicit one on any joint, at the end's (ServoStage::implicitSpring).
    if (!m.joints[ji].movable()) continue;
    const bool implicit = servos.implicitSpring(ji);
    if (!implicit && drives[ji].mode != JointDrive::Mode::kPassive) continue;
    const double d = servos.damping(ji);
    if (d <= 0.0) continue;
    const int l = m.joints[ji].child_link - 1;
    const double q0 = servos.startVelocity(l), q1 = mb.getJointVel(l);
    damping_work_ -= h * d * (implicit ? q1 : q0) * 0.5 * (q0 + q1);
  }
}

void stateEnergies(const CreatureModel& m, const BulletBody& body, const CreatureFluid& fluid,
                   const ServoStage& servos, const AirParams& air, const Vec3& gravity,
                   double piece, CreatureEnergy& out) {
  const LinkFrames& frames = body.frames();
  out.kinetic = out.potential = out.spring = out.fluid_kinetic = 0.0;
  for (size_t k = 0; k < m.links.size(); ++k) {
    const LinkModel& l = m.links[k];
    const BodyKinematics kin = frames.kinematics(static_cast<int>(k));
    const Vec3 w = kin.body_angular_velocity;
    out.kinetic += 0.5 * l.mass * (kin.linear_velocity - air.wind).squaredNorm() +
                   0.5 * w.dot(l.inertia.cwiseProduct(w));
    out.potential -= l.mass * gravity.dot(kin.com - 0.5 * piece * kin.linear_velocity);
  }
  const btMultiBody& mb = body.multiBody();
  for (size_t ji = 0; ji < m.joints.size(); ++ji) {
    const JointModel& j = m.joints[ji];
    if (!j.movable() || servos.stiffness(ji) <= 0.0) continue;
    const double q = mb.getJointPos(j.child_link - 1) - j.reference;
    out.spring += 0.5 * servos.stiffness(ji) * q * q;
  }
  if (!air.enabled || air.density <= 0.0) return;
  for (const AeroBody& a : fluid.bodies()) {
    if (!a.has_added_mass) continue;
    const BodyKinematics kin = frames.kinematics(a.link);
    Vec6 nu;
    nu << kin.body_angular_velocity, kin.rotation.transpose() * (kin.linear_velocity - air.wind);
    out.fluid_kinetic += 0.5 * air.density * nu.dot(a.added_mass * nu);
  }
}

}  // namespace flapsim
