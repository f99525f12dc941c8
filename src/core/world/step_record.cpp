#include "world/step_record.h"

#include <algorithm>

#include "dynamics/bullet_body.h"
#include "dynamics/servo_stage.h"
#include "fluid/creature_fluid.h"
#include "world/power.h"

namespace flapsim {

StepRecord::StepRecord(const CreatureModel& m) : model_(m) {
  for (const JointModel& j : m.joints) joint_link_.push_back(static_cast<size_t>(j.child_link));
  clear();
}

void StepRecord::clear() {
  const size_t links = model_.links.size(), joints = model_.joints.size();
  data_.step = 0.0;
  data_.substeps = 0;
  data_.contact = false;
  data_.com.assign(links, Vec3::Zero());
  data_.fluid_wrench.assign(links, Wrench());
  data_.external_wrench.assign(links, Wrench());
  data_.servo_effort.assign(joints, 0.0);
  data_.joint_power.assign(joints, 0.0);
  data_.total_power = 0.0;
}

void StepRecord::beginStep(const LinkFrames& frames, double dt) {
  dt_ = dt;
  data_.step = 0.0;  // until endStep()
  data_.substeps = 0;
  data_.contact = false;
  for (size_t k = 0; k < data_.com.size(); ++k) {
    data_.com[k] = fromBt(frames.com(static_cast<int>(k)));
  }
  std::fill(data_.fluid_wrench.begin(), data_.fluid_wrench.end(), Wrench());
  if (external_) {
    std::fill(data_.external_wrench.begin(), data_.external_wrench.end(), Wrench());
    external_ = false;
  }
  std::fill(data_.servo_effort.begin(), data_.servo_effort.end(), 0.0);
  // joint_power and total_power: endStep() writes them.
}

void StepRecord::beginSubStep(const LinkFrames& frames, double h) {
  ++data_.substeps;
  whole_ = h == dt_;
  weight_ = h / dt_;
  sub_origin_ = fromBt(frames.com(0));
}

void StepRecord::add(Wrench& total, int k, const Vec3& point, const Wrench& wrench) const {
  if (whole_) {  // a step in one piece: the point is the COM of its start, the weight 1
    total += wrench;
    return;
  }
  total.force += weight_ * wrench.force;
  total.torque += weight_ * (wrench.torque + (point - data_.com[k]).cross(wrench.force));
}

void StepRecord::fluid(const CreatureFluid& fluid, bool air) {
  if (!air) return;  // the stage did not run: the aero bodies' `last` is an older step's
  for (const AeroBody& a : fluid.bodies()) {
    add(data_.fluid_wrench[a.link], a.link, a.last.com, a.last.wrench);
  }
}

void StepRecord::external(int link, const Vec3& com, const Wrench& wrench) {
  add(data_.external_wrench[link], link, com, wrench);
  external_ = true;
}

void StepRecord::servos(const ServoStage& servos, const CreatureFluid& fluid) {
  // Impulses over the (sub)step: over the step's length, their mean force.
  const std::vector<AeroBody>& aero = fluid.bodies();
  for (size_t i = 0; i < aero.size(); ++i) {
    if (aero[i].drag_zero) continue;                   // no implicit drag on it in this (sub)step
    const Vec6 impulse = servos.dragImpulse(i) / dt_;  // about the root's COM
    const int k = aero[i].link;
    Wrench& total = data_.fluid_wrench[k];
    total.force += impulse.tail<3>();
    total.torque += momentAbout(impulse, sub_origin_, data_.com[k]);
  }
  const std::vector<double>& impulse = servos.solution().impulse;
  for (size_t j = 0; j < joint_link_.size(); ++j) {
    const size_t k = joint_link_[j];
    // As ServoStage::effort() divides it: in a step of one piece, CreatureState's to the bit.
    if (k < impulse.size() && impulse[k] != 0.0) data_.servo_effort[j] += impulse[k] / dt_;
  }
}

void StepRecord::endStep(const PowerMeter& power) {
  data_.step = dt_;
  const std::vector<double>& work = power.stepWork();
  data_.total_power = 0.0;
  for (size_t j = 0; j < data_.joint_power.size(); ++j) {
    data_.joint_power[j] = work[j] / dt_;  // World::power's, to the bit
    data_.total_power += data_.joint_power[j];
  }
}

}  // namespace flapsim
