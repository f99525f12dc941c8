// Which step sizes a creature may be flown at: a step is accurate for a creature when an open-
// loop flight at it stays finite and not diverged, and changes height within
// kStepTolerance of the same flight at a reference step of 1/16 ms (the same world, turn
// substeps included). Evolution draws its step sizes from the accurate ones (evolve
// --step-sizes auto). No clock.
#pragma once

#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/stroke.h"
#include "flapsim/world.h"

namespace flapsim {

constexpr double kStepTolerance = 0.05;       // of the reference's height change
constexpr double kReferenceStep = 0.0000625;  // s
constexpr double kAccuracySeconds = 3.0;      // s of open-loop flight

/// One flight's figures at one step.
struct StepFlight {
  double step = 0.0;
  bool finite = true;          // not diverged
  double height_change = 0.0;  // m, of the root after kAccuracySeconds
};

/// The verdict at one step against the reference.
struct StepVerdict {
  StepFlight flight, reference;
  double relativeError() const;  // |dz - dz_ref| / |dz_ref|
  /// Empty if accurate, else why not.
  std::string why() const;
};

/// `model` flown level from 50 m (no ground) with `stroke` on every wing in `world` (its air,
/// gravity and turn substep), at `step`.
StepFlight flyOpenLoop(const CreatureModelPtr& model, const StrokeCommand& stroke,
                       WorldParams world, double step);

/// The verdicts at each of `candidates` (s) against one reference flight.
std::vector<StepVerdict> stepVerdicts(const CreatureModelPtr& model, const StrokeCommand& stroke,
                                      const WorldParams& world,
                                      const std::vector<double>& candidates);

/// The step sizes evolution draws from: the largest accurate candidate h of 4, 2, 1 and 0.5 ms
/// and h / 2 (the smallest pair if none is).
std::vector<double> accurateStepSizes(const CreatureModelPtr& model, const StrokeCommand& stroke,
                                      const WorldParams& world);

}  // namespace flapsim
