// Which step sizes a creature may be flown at: a step is accurate for a creature when an open-
// loop flight at it stays finite and not diverged, and changes height within
// kStepTolerance of the same flight at a reference step of 1/16 ms (the same world, turn
// substeps included). Evolution draws its step sizes from the accurate ones, with the turn
// substep chosen together with them (evolve --step-sizes auto). No clock.
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
  double turn_substep = 0.0;   // s, the world's
  bool finite = true;          // not diverged
  double height_change = 0.0;  // m, of the root after kAccuracySeconds
  long substeps = 0;           // the (sub)steps the flight was taken in: its cost
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

/// The value of a tool's turn-substep flag `flag` (evolve's and flight_check's --turn-substep):
/// a number in [0, 0.1] s that WorldParams takes, else an InputError naming the flag.
double turnSubstepFromFlag(const std::string& flag, const std::string& text);

/// What evolution flies a creature at: two step sizes, h and h / 2, and one turn substep.
struct StepChoice {
  std::vector<double> step_sizes;
  double turn_substep = 0.0;
  bool operator==(const StepChoice& o) const {
    return step_sizes == o.step_sizes && turn_substep == o.turn_substep;
  }
};

/// A candidate setting and its two flights' verdicts (at h and h / 2, the same turn substep).
struct StepCandidate {
  double step = 0.0, turn_substep = 0.0;
  StepVerdict at_step, at_half;  // at_half is flown only when at_step is accurate
  bool accurate() const;
  long substeps() const;  // of the two flights
};

/// Every candidate of accurateStepChoice, in the order tried: h of 4, 2, 1 and 0.5 ms, each
/// with a turn substep of h, h / 2 and h / 4 that is at least 0.5 ms (`turn_substep` >= 0:
/// that one only).
std::vector<StepCandidate> stepCandidates(const CreatureModelPtr& model,
                                          const StrokeCommand& stroke, const WorldParams& world,
                                          double turn_substep = -1.0);

/// The cheapest accurate candidate (the fewest substeps over its two flights; of equal ones
/// the larger step, then the larger turn substep); if none is accurate, 0.5 and 0.25 ms at the
/// world's turn substep.
StepChoice accurateStepChoice(const CreatureModelPtr& model, const StrokeCommand& stroke,
                              const WorldParams& world, double turn_substep = -1.0);

}  // namespace flapsim
