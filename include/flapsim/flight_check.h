// The flight check: a creature flown by its controller from held-out starts (a seed of its
// own, not the evolution's), each reported as flipped or not, its lowest up-component, its
// final and lowest height and the fraction of time it was upright. Used by the
// flight_check executable and the tests. ROS-free; no clock.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"

namespace flapsim {

struct FlightCheckParams {
  int starts = 20;
  std::uint64_t seed = 2024;  // held out: evolution draws its starts from mixSeed(ga seed)
  double max_roll = 0.26;     // rad (15 deg): roll uniform in +-max_roll
  double max_pitch = 0.26;    // rad: pitch uniform in +-max_pitch
  double duration = 60.0;     // s
  double start_height = 1.0;  // m, root body
  double step_size = 0.001;   // s
  int threads = 1;            // results do not depend on it
};

struct FlightCheckRun {
  EpisodeStart start;
  bool flipped = false;       // the root's up axis went below the horizon
  double min_upright = 1.0;   // lowest up-component of the root body
  double final_height = 0.0;  // m
  double min_height = 0.0;    // m
  double upright_fraction = 0.0;
  double positive_power = 0.0;  // W: the motors' mean positive mechanical power
  double net_power = 0.0;       // W: their mean net mechanical power
  double mass = 0.0;            // kg
  /// No flip, up-component never below 0.5, final height above the start.
  bool passed(double start_height) const {
    return !flipped && min_upright >= 0.5 && final_height > start_height;
  }
};

/// Flies `model` under `controller` (the same network on every unit) from `params.starts`
/// starts drawn from `params.seed`. Throws InputError for bad parameters.
std::vector<FlightCheckRun> flightCheck(const CreatureModelPtr& model,
                                        const ControllerSpec& controller,
                                        const FlightCheckParams& params);

}  // namespace flapsim
