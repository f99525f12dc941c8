// The step data of a creature (flapsim/step_data.h) as the stages of its step write it
// (world/creature_step.h): each stage adds its named outputs of a (sub)step, weighted by the
// (sub)step's share of the step, and the power stage closes the step. Private to flapsim_core.
#pragma once

#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/step_data.h"

namespace flapsim {

class LinkFrames;
class CreatureFluid;
class PowerMeter;
class ServoStage;

class StepRecord {
 public:
  // Sized for creature `m` (which must outlive the record), no step yet.
  explicit StepRecord(const CreatureModel& m);

  // No step: after the state was set from outside a step, and after a refused step.
  void clear();
  // The start of a step of `dt` (`frames`: of its start).
  void beginStep(const LinkFrames& frames, double dt);
  // The start of a (sub)step of `h` (`frames`: of its start).
  void beginSubStep(const LinkFrames& frames, double h);
  // The fluid stage's wrenches (AeroBody::last) held over the (sub)step; `air`: the stage ran.
  void fluid(const CreatureFluid& fluid, bool air);
  // The external stage's wrench on link `link` about its COM `com` (the (sub)step's start).
  void external(int link, const Vec3& com, const Wrench& wrench);
  // The servo stage's solve: the servos' impulses and the implicit drag's.
  void servos(const ServoStage& servos, const CreatureFluid& fluid);
  // The constraints stage: whether the creature touched anything.
  void contact(bool touching) { data_.contact = data_.contact || touching; }
  // The power stage, at the end of the step: each motor's work over it.
  void endStep(const PowerMeter& power);

  const StepData& data() const { return data_; }

 private:
  // Adds `wrench` about `point` held over the (sub)step to link k's `total` (about the COM of
  // the step's start).
  void add(Wrench& total, int k, const Vec3& point, const Wrench& wrench) const;

  const CreatureModel& model_;
  std::vector<size_t> joint_link_;  // per model joint: its child link
  StepData data_;
  double dt_ = 0.0;                 // the step's length
  double weight_ = 0.0;             // the (sub)step's share of it
  bool whole_ = false;              // the (sub)step is the whole step
  bool external_ = false;           // an external wrench was recorded since the step began
  Vec3 sub_origin_ = Vec3::Zero();  // the root's COM at the (sub)step's start
};

}  // namespace flapsim
