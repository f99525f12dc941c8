// roll_damping: how far a creature rolls from a spin, its roll control off. Prints figures;
// never passes or fails.
//
//   roll_damping [--rate 5] [--duration 1] [--step-size 0.001]
//
// Each creature starts level in still air, spinning at --rate rad/s about the world's x axis
// (its roll), and flies --duration s with nothing that answers the roll: afc_1 stroking open
// loop (both wings 40 rad/s down, 20 up, amplitude 1.2 rad), hover_1 and config/morph_shed
// under their gains with the roll loop off (max_roll_share 0; the height and pitch loops on).
// Printed: the largest bank it reaches (asin(world_up . body_left)), the same without the spin
// (what the strokes and the start do by themselves), and the rate over their difference, which
// for a body whose roll the air damps as c x rate is c / I (1/s): how much of a spin the air
// takes out, per second. Held rigid in vacuum, nothing stops the spin.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "flapsim/ann.h"
#include "flapsim/cli_args.h"
#include "flapsim/evolve.h"
#include "flapsim/hover_flight.h"
#include "flapsim/hover_gains.h"
#include "flapsim/make_creature.h"

namespace {

// The line of a creature whose largest bank is `spun` from the spin `rate` and `still` without
// it (rad).
void print(const char* name, double spun, double still, double rate) {
  std::printf(
      "%-36s largest bank %6.1f deg (without the spin %5.1f), rate / difference %6.2f 1/s\n", name,
      spun * 180.0 / M_PI, still * 180.0 / M_PI, rate / (spun - still));
}

// The largest bank (rad) of afc_1 stroking open loop from a spin of `rate` about x, over the
// control updates.
double flapUnitBank(double rate, double duration, double step) {
  const auto model = flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(1, "afc"), "afc1");
  flapsim::EpisodeParams e;
  e.duration = duration;
  e.start_height = 5.0;
  e.world.step_size = step;
  flapsim::EpisodeStart start;
  start.rate = flapsim::Vec3(rate, 0.0, 0.0);
  flapsim::StrokeCommand stroke;
  stroke.downstroke_rate = 40.0;
  stroke.upstroke_rate = 20.0;
  stroke.amplitude = 1.2;
  const flapsim::OpenLoopWingController open(stroke);
  double bank = 0.0;
  for (const flapsim::EpisodeSample& x :
       flapsim::runEpisode(model, open, 0.02, e, start, true).trace) {
    bank = std::max(bank, std::abs(flapsim::bankAngle(x.root.orientation)));
  }
  return bank;
}

// The largest bank (rad) of a hover creature (`urdf` empty: hover_1) under `gains` with its roll
// loop off, from a spin of `rate` about x, over the steps.
double hoverBank(const std::string& urdf, const std::string& gains, double rate, double duration,
                 double step) {
  const flapsim::CreatureModelPtr model =
      urdf.empty() ? flapsim::parseCreatureModel(flapsim::makeHoverUrdf("hover"), "hover_1")
                   : flapsim::loadCreatureModel(urdf);
  flapsim::HoverControllerParams g = flapsim::loadHoverGainsYaml(gains);
  g.max_roll_share = 0.0;
  flapsim::HoverFlightParams f;
  f.duration = duration;
  f.settle = 0.0;
  f.start_rate = flapsim::Vec3(rate, 0.0, 0.0);
  f.world.step_size = step;
  return flapsim::flyHover(model, g, f).largest_bank;
}

}  // namespace

int main(int argc, char** argv) {
  double rate = 5.0, duration = 1.0, step = 0.001;
  flapsim::CliParser cli("usage: roll_damping [options]");
  cli.real("--rate", "W", &rate, {0.01, 100}, "the start's spin about x, rad/s")
      .real("--duration", "S", &duration, {0.02, 60}, "s flown")
      .real("--step-size", "DT", &step, {1e-6, 0.01}, "s");
  try {
    cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    if (cli.help()) {
      std::printf("%s", cli.usage().c_str());
      return 0;
    }
    std::printf("a spin of %g rad/s about x, %g s flown, roll control off, %g ms steps:\n", rate,
                duration, step * 1e3);
    print("afc_1, open loop (40 / 20 rad/s)", flapUnitBank(rate, duration, step),
          flapUnitBank(0.0, duration, step), rate);
    for (const auto& [name, urdf, gains] :
         {std::tuple{"hover_1, its gains", "", "config/hover_1_gains.yaml"},
          std::tuple{"config/morph_shed, its gains", "config/morph_shed/creature.urdf",
                     "config/morph_shed/gains.yaml"}}) {
      print(name, hoverBank(urdf, gains, rate, duration, step),
            hoverBank(urdf, gains, 0.0, duration, step), rate);
    }
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "roll_damping: %s\n", ex.what());
    return 2;
  }
  return 0;
}
