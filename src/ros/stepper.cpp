#include "flapsim_ros/stepper.h"

#include <algorithm>
#include <cmath>

#include "flapsim_ros/conversions.h"

namespace flapsim_ros {
namespace {

constexpr double kMaxPacingLag = 0.25;  // s (wall) behind schedule before pacing restarts
constexpr double kPausedPoll = 0.1;     // s (wall) longest callback wait (shutdown is seen)
constexpr double kRunSlice = 0.05;      // s (wall) of stepping between callback rounds
// Steps between checks of the wall time and shutdown: at most this many, and as many as take
// about kSliceTarget of wall time (one, for a slow step: a long chain on the ground).
constexpr std::uint64_t kSliceSteps = 10;
constexpr double kSliceTarget = 0.01;  // s (wall)

}  // namespace

Stepper::Stepper(flapsim::World& world, CreatureRegistry& creatures, WorldPublishers& publishers,
                 NodeDiagnostics& diagnostics, const NodeParams& params)
    : world_(world),
      creatures_(creatures),
      publishers_(publishers),
      diagnostics_(diagnostics),
      params_(params),
      paused_(params.paused) {}

std::uint64_t Stepper::advance(std::uint64_t steps, double wall_budget) {
  const ros::WallTime start = ros::WallTime::now();
  const std::uint64_t every = publishEvery(params_);
  std::uint64_t taken = 0;
  while (taken < steps && ros::ok()) {
    const std::uint64_t to_boundary = every - world_.stepCount() % every;
    const std::uint64_t k = std::min({steps - taken, to_boundary, slice_steps_});
    world_.setRecordCellForces(publishers_.wantsCellForces());
    const ros::WallTime chunk_start = ros::WallTime::now();
    world_.step(static_cast<int>(k));
    const double per_step = (ros::WallTime::now() - chunk_start).toSec() / static_cast<double>(k);
    slice_steps_ = std::clamp<std::uint64_t>(
        per_step > 0.0 ? static_cast<std::uint64_t>(kSliceTarget / per_step) : kSliceSteps, 1,
        kSliceSteps);
    taken += k;
    reportEvents();
    if (world_.stepCount() % every == 0) publishers_.publishAll();
    if (wall_budget > 0.0 && (ros::WallTime::now() - start).toSec() > wall_budget) break;
  }
  return taken;
}

void Stepper::reportEvents() {
  const std::uint64_t step_ns = stepNanoseconds(params_.world.step_size);
  const std::vector<flapsim::CommandLapse> lapses = world_.takeCommandLapses();
  const bool hold = params_.wing_command_timeout_action == CommandTimeoutAction::kHold;
  for (const flapsim::CommandLapse& l : lapses) {
    creatures_.warn(
        "wing_command_timeout", l.creature,
        "creature '" + l.creature + "': no wing command for " +
            std::to_string(params_.wing_command_timeout) +
            " s of sim time (since t = " + formatTime(simTime(l.commanded_step, step_ns)) +
            " s): wings " + (hold ? "held" : "released") + " until the next command");
  }
  const std::vector<flapsim::Divergence> frozen = world_.takeDivergences();
  for (const flapsim::Divergence& d : frozen) {
    ROS_ERROR_STREAM("flapsim: creature '"
                     << d.creature << "' diverged at step " << d.step
                     << " (t = " << formatTime(simTime(d.step, step_ns)) << " s): " << d.quantity
                     << "; frozen at its last good state until flapsim/reset or flapsim/delete");
  }
  if (!lapses.empty() || !frozen.empty()) diagnostics_.publish();
}

void Stepper::runSlice(ros::CallbackQueue& queue) {
  const std::uint64_t every = publishEvery(params_);
  advance(every - world_.stepCount() % every, kRunSlice);
  queue.callAvailable();
  if (paused_ || params_.real_time_factor <= 0.0) return;
  const double sim_elapsed =
      static_cast<double>(world_.stepCount() - pace_step_) * params_.world.step_size;
  const ros::WallTime due = pace_wall_ + ros::WallDuration(sim_elapsed / params_.real_time_factor);
  ros::WallTime wall = ros::WallTime::now();
  if (wall > due + ros::WallDuration(kMaxPacingLag)) {
    restartPacing();  // too slow for this factor: run as fast as possible, don't burst
    return;
  }
  while (ros::ok() && !paused_ && wall < due) {
    queue.callAvailable(std::min(due - wall, ros::WallDuration(kPausedPoll)));
    wall = ros::WallTime::now();
  }
}

void Stepper::restartPacing() {
  pace_wall_ = ros::WallTime::now();
  pace_step_ = world_.stepCount();
}

}  // namespace flapsim_ros
