#include "flapsim/step_accuracy.h"

#include <cmath>
#include <cstdio>

#include "flapsim/cli_args.h"

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
  f.turn_substep = world.turn_substep;
  const int steps = static_cast<int>(std::lround(kAccuracySeconds / step));
  for (int k = 0; k < steps; ++k) {
    w.step(1);
    f.substeps += w.stepData("c").substeps;
  }
  f.finite = !w.divergence("c");
  f.height_change = w.rootPose("c").position.z() - 50.0;
  return f;
}

double turnSubstepFromFlag(const std::string& flag, const std::string& text) {
  WorldParams world;
  world.turn_substep = parseCliReal(flag, text, {0, 0.1});
  const std::string err = validateWorldParams(world);
  if (!err.empty()) throw InputError(flag + ": " + err);
  return world.turn_substep;
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

bool StepCandidate::accurate() const {
  return at_step.why().empty() && at_half.flight.step > 0.0 && at_half.why().empty();
}

long StepCandidate::substeps() const { return at_step.flight.substeps + at_half.flight.substeps; }

std::vector<StepCandidate> stepCandidates(const CreatureModelPtr& model,
                                          const StrokeCommand& stroke, const WorldParams& world,
                                          double turn_substep) {
  constexpr double kShortestTurnSubstep = 0.0005;
  const StepFlight reference = flyOpenLoop(model, stroke, world, kReferenceStep);
  std::vector<StepCandidate> out;
  for (double h : {0.004, 0.002, 0.001, 0.0005}) {
    std::vector<double> substeps = {turn_substep};
    if (turn_substep < 0.0) {
      substeps.clear();
      for (double s : {h, h / 2.0, h / 4.0}) {
        if (s >= kShortestTurnSubstep * (1.0 - 1e-9)) substeps.push_back(s);
      }
    }
    for (double s : substeps) {
      WorldParams at = world;
      at.turn_substep = s;
      StepCandidate c;
      c.step = h;
      c.turn_substep = s;
      c.at_step = StepVerdict{flyOpenLoop(model, stroke, at, h), reference};
      if (c.at_step.why().empty())
        c.at_half = StepVerdict{flyOpenLoop(model, stroke, at, h / 2.0), reference};
      out.push_back(c);
    }
  }
  return out;
}

StepChoice accurateStepChoice(const CreatureModelPtr& model, const StrokeCommand& stroke,
                              const WorldParams& world, double turn_substep) {
  const StepCandidate* best = nullptr;
  const std::vector<StepCandidate> all = stepCandidates(model, stroke, world, turn_substep);
  for (const StepCandidate& c : all) {
    // In the order tried (larger steps, then larger substeps first): only fewer substeps win.
    if (c.accurate() && (best == nullptr || c.substeps() < best->substeps())) best = &c;
  }
  if (best == nullptr) {
    return {{0.0005, 0.00025}, turn_substep >= 0.0 ? turn_substep : world.turn_substep};
  }
  return {{best->step, best->step / 2.0}, best->turn_substep};
}

}  // namespace flapsim
