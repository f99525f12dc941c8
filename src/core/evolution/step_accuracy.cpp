#include "flapsim/step_accuracy.h"

#include <cmath>
#include <cstdio>

namespace flapsim {

StepFlight flyOpenLoop(const CreatureModelPtr& model, const StrokeCommand& stroke,
                       WorldParams world, double step) {
  world.step_size = step;
  world.ground = false;
  World w(world);
  w.spawn("c", model, Pose{Vec3(0.0, 0.0, 50.0), Quat::Identity()});
  w.setWingCommands("c", {}, std::vector<StrokeCommand>(model->wing_joints.size(), stroke));
  StepFlight f;
  f.step = step;
  const int steps = static_cast<int>(std::lround(kAccuracySeconds / step));
  w.step(steps);
  f.finite = !w.divergence("c");
  f.height_change = w.rootPose("c").position.z() - 50.0;
  return f;
}

double StepVerdict::relativeError() const {
  return std::abs(flight.height_change - reference.height_change) /
         std::max(1e-12, std::abs(reference.height_change));
}

std::string StepVerdict::why() const {
  char out[160];
  if (!flight.finite) return "diverged";
  if (relativeError() > kStepTolerance) {
    std::snprintf(out, sizeof out, "height change %.4f m against the reference's %.4f m (%.1f %%)",
                  flight.height_change, reference.height_change, 100.0 * relativeError());
    return out;
  }
  return "";
}

std::vector<StepVerdict> stepVerdicts(const CreatureModelPtr& model, const StrokeCommand& stroke,
                                      const WorldParams& world,
                                      const std::vector<double>& candidates) {
  const StepFlight reference = flyOpenLoop(model, stroke, world, kReferenceStep);
  std::vector<StepVerdict> out;
  for (double step : candidates)
    out.push_back({flyOpenLoop(model, stroke, world, step), reference});
  return out;
}

std::vector<double> accurateStepSizes(const CreatureModelPtr& model, const StrokeCommand& stroke,
                                      const WorldParams& world) {
  const std::vector<double> candidates = {0.004, 0.002, 0.001, 0.0005};
  // The largest first: stop at the first accurate one.
  const StepFlight reference = flyOpenLoop(model, stroke, world, kReferenceStep);
  for (double step : candidates) {
    if (StepVerdict{flyOpenLoop(model, stroke, world, step), reference}.why().empty()) {
      return {step, step / 2.0};
    }
  }
  return {candidates.back(), candidates.back() / 2.0};
}

}  // namespace flapsim
