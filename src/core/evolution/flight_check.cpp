#include "flapsim/flight_check.h"

#include <cmath>

#include "flapsim/ga.h"

namespace flapsim {

namespace {

// The episodes the flight check flies (its starts are their episodeStarts()).
EpisodeParams flightCheckEpisodes(const FlightCheckParams& p) {
  if (p.starts < 1) throw InputError("flight check: starts must be >= 1");
  EpisodeParams episode;
  episode.duration = p.duration;
  episode.start_height = p.start_height;
  episode.min_roll = 0.0;
  episode.max_roll = p.max_roll;
  episode.max_pitch = p.max_pitch;
  episode.episodes = p.starts;
  episode.seed = p.seed;
  episode.world.step_size = p.step_size;
  const std::string err = validateEpisodeParams(episode);
  if (!err.empty()) throw InputError("flight check: " + err);
  return episode;
}

}  // namespace

std::vector<FlightCheckRun> flightCheck(const CreatureModelPtr& model,
                                        const ControllerSpec& controller,
                                        const FlightCheckParams& p) {
  if (p.threads < 1) throw InputError("flight check: threads must be >= 1");
  const EpisodeParams episode = flightCheckEpisodes(p);
  // Roll uniform in +-max_roll (episodeStarts alternates the sign of |roll| in [0, max]).
  const std::vector<EpisodeStart> starts = episodeStarts(episode);
  const AnnWingController ann(FlapUnitController(controller.params, controller.weights));
  std::vector<FlightCheckRun> runs(starts.size());
  parallelMap(static_cast<int>(starts.size()), p.threads, [&](int i) {
    const EpisodeResult r =
        runEpisode(model, ann, controller.params.control_period, episode, starts[i]);
    FlightCheckRun& run = runs[i];
    run.start = starts[i];
    run.flipped = r.flipped;
    run.min_upright = r.min_upright;
    run.final_height = r.final_height;
    run.min_height = r.min_height;
    run.upright_fraction = r.upright_fraction;
    run.positive_power = r.positive_power;
    run.net_power = r.net_power;
    run.mass = r.mass;
    return 0.0;
  });
  return runs;
}

}  // namespace flapsim
