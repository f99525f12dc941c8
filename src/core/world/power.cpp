#include "world/power.h"

#include <algorithm>

namespace flapsim {

double CreaturePower::totalPower() const {
  double sum = 0.0;
  for (double p : power) sum += p;
  return sum;
}

double CreaturePower::totalWork() const {
  double sum = 0.0;
  for (double w : work) sum += w;
  return sum;
}

double CreaturePower::totalPositiveWork() const {
  double sum = 0.0;
  for (double w : positive_work) sum += w;
  return sum;
}

double CreaturePower::meanPositivePower() const {
  return time > 0.0 ? totalPositiveWork() / time : 0.0;
}

bool motorWorkMeterFromName(const std::string& name, MotorWorkMeter* out) {
  if (name == "transmitted") {
    *out = MotorWorkMeter::kTransmitted;
  } else if (name == "servo") {
    *out = MotorWorkMeter::kServoImpulse;
  } else {
    return false;
  }
  return true;
}

const char* motorWorkMeterName(MotorWorkMeter meter) {
  return meter == MotorWorkMeter::kTransmitted ? "transmitted" : "servo";
}

void PowerMeter::reset(size_t joints) {
  energy_.assign(joints, JointEnergy());
  before_ = energy_;
  step_work_.assign(joints, 0.0);
  time_ = 0.0;
  last_step_ = 0.0;
}

void PowerMeter::beginStep() {
  before_ = energy_;
  std::fill(step_work_.begin(), step_work_.end(), 0.0);
}

namespace {

// Whether joint `j` has a motor at work: driven by a stroke or a velocity target, or the
// feather joint of a stroking wing.
bool motorAt(const CreatureModel& m, const std::vector<JointDrive>& drives, size_t j) {
  if (drives[j].mode != JointDrive::Mode::kPassive) return true;
  for (int w : m.wing_joints) {
    if (m.joints[w].feather_joint == static_cast<int>(j) &&
        drives[w].mode == JointDrive::Mode::kStroke) {
      return true;
    }
  }
  return false;
}

}  // namespace

void PowerMeter::endSubStep(const CreatureModel& m, const std::vector<JointDrive>& drives,
                            const btMultiBody& mb, const ServoStage& servos,
                            const TransmittedWork* transmitted, double h) {
  const std::vector<double>& impulse = servos.solution().impulse;
  for (size_t j = 0; j < m.joints.size(); ++j) {
    const JointModel& joint = m.joints[j];
    const size_t k = static_cast<size_t>(joint.child_link);
    if (!joint.movable() || k >= impulse.size() || impulse[k] == 0.0) continue;
    if (!motorAt(m, drives, j)) continue;
    double work;
    if (transmitted != nullptr && transmitted->known()) {
      work = transmitted->work(j, servos, mb, h);
    } else {
      // Over the trapezoid of the joint's velocities: what the impulse gives the bodies'
      // kinetic energy (a servo that meets its target within the (sub)step changes the
      // velocity at once, and the position then moves by step x the end velocity; counted
      // so, a wing's reversal in vacuum drew 13 % more work at 1 ms than its bodies took up).
      // A saturated servo's joint moves by that trapezoid itself
      // (ServoStage::integrateSaturated).
      const int link = static_cast<int>(k) - 1;
      work =
          motorWork(impulse[k], h, 0.5 * h * (servos.startVelocity(link) + mb.getJointVel(link)));
    }
    energy_[j].add(work);
    step_work_[j] += work;
  }
}

void PowerMeter::endStep(double dt) {
  time_ += dt;
  last_step_ = dt;
}

void PowerMeter::undoStep() {
  energy_ = before_;
  std::fill(step_work_.begin(), step_work_.end(), 0.0);
}

CreaturePower PowerMeter::report(double mass) const {
  CreaturePower p;
  p.time = time_;
  p.mass = mass;
  p.power.resize(energy_.size());
  p.work.resize(energy_.size());
  p.positive_work.resize(energy_.size());
  for (size_t j = 0; j < energy_.size(); ++j) {
    p.power[j] = last_step_ > 0.0 ? step_work_[j] / last_step_ : 0.0;
    p.work[j] = energy_[j].work;
    p.positive_work[j] = energy_[j].positive_work;
  }
  return p;
}

}  // namespace flapsim
