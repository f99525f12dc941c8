// push_oracle: how much roll authority a flap unit has against a push on a wing. Prints
// figures; never passes or fails.
//
//   push_oracle --weights FILE [--starts 20] [--seed 2024] [--force 1] [--step-size 0.001]
//               [--after 4]
//
// flight_check's held-out starts (+-30 deg, a push of --force N on a drawn wing, up or down,
// for 0.2 s at a drawn time in 10-60 % of a 60 s flight) flown by the network of FILE (without
// its roll reflex, if it has one) until --after s past the push (a flip ends a flight), first
// alone, then with an oracle that knows the push (wing, sign, time) and replaces the network's
// strokes over it by a fixed counter pattern: the pushed wing's half-stroke along the push at
// 65 rad/s and the other slow (10, 20 or 27 rad/s), so the air pushes it back; the other wing
// the other way round; nine rate pairs, from 0 or 0.1 s before the push to 0, 0.1 or 0.3 s
// after it. Per start: whether the network alone flips, how many of the 54 patterns keep it
// upright, and the best one. doc/flight_and_evolution.md quotes it: with upstrokes as fast
// as the downstrokes the push is survivable, which the roll reflex
// (FlapControllerParams::roll_reflex_bank) exploits without knowing the push.
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "flapsim/ann.h"
#include "flapsim/cli_args.h"
#include "flapsim/controller_file.h"
#include "flapsim/evolve.h"
#include "flapsim/flight_check.h"
#include "flapsim/make_creature.h"

namespace {

using flapsim::AnnWingController;
using flapsim::FlapSensing;
using flapsim::StrokeCommand;

// The network, except from t0 to t1 (s of flight), when the wings get `left` and `right`.
class PushOracle : public flapsim::WingController {
 public:
  PushOracle(const AnnWingController& net, double period) : net_(net), period_(period) {}
  void counter(double t0, double t1, const StrokeCommand& left, const StrokeCommand& right) {
    t0_ = t0;
    t1_ = t1;
    left_ = left;
    right_ = right;
  }
  std::vector<StrokeCommand> commands(const FlapSensing& sensed) const override {
    const double t = static_cast<double>(calls_++) * period_;  // one call per control period
    std::vector<StrokeCommand> c = net_.commands(sensed);
    if (t >= t0_ && t < t1_) {
      c[0] = left_;
      c[1] = right_;
    }
    return c;
  }

 private:
  const AnnWingController& net_;
  double period_;
  double t0_ = 0.0, t1_ = 0.0;
  StrokeCommand left_, right_;
  mutable long calls_ = 0;
};

// What the 54 counter patterns do for the start `s` (a push `up` or down, on the left wing
// if `left_pushed`): how many keep it upright, and the best (the highest lowest up).
struct Patterns {
  int upright = 0, tried = 0;
  double best_up = -2.0;
  char best[128] = "";
};

Patterns tryPatterns(const flapsim::CreatureModelPtr& model, const AnnWingController& net,
                     double period, const flapsim::EpisodeParams& run,
                     const flapsim::EpisodeStart& s, const StrokeCommand& stroke, bool up,
                     bool left_pushed) {
  Patterns out;
  for (double lead : {0.0, 0.1}) {
    for (double tail : {0.0, 0.1, 0.3}) {
      for (double slow_pushed : {10.0, 20.0, 27.0}) {
        for (double slow_other : {10.0, 20.0, 27.0}) {
          // The pushed wing: the air against the push; the other: the air along the
          // counter-roll.
          StrokeCommand pushed = stroke, other = stroke;
          pushed.downstroke_rate = up ? slow_pushed : 65.0;
          pushed.upstroke_rate = up ? 65.0 : slow_pushed;
          other.downstroke_rate = up ? 65.0 : slow_other;
          other.upstroke_rate = up ? slow_other : 65.0;
          PushOracle oracle(net, period);
          oracle.counter(s.force_time - lead, s.force_time + 0.2 + tail,
                         left_pushed ? pushed : other, left_pushed ? other : pushed);
          const flapsim::EpisodeResult r = flapsim::runEpisode(model, oracle, period, run, s);
          ++out.tried;
          out.upright += !r.flipped;
          if (r.min_upright > out.best_up) {
            out.best_up = r.min_upright;
            std::snprintf(out.best, sizeof out.best,
                          "%.1f s before to %.1f s after its start: pushed %g/%g, other %g/%g",
                          lead, 0.2 + tail, pushed.downstroke_rate, pushed.upstroke_rate,
                          other.downstroke_rate, other.upstroke_rate);
          }
        }
      }
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string weights;
  int starts = 20;
  std::uint64_t seed = 2024;
  double force = 1.0, step = 0.001, after = 4.0;
  flapsim::CliParser cli("usage: push_oracle --weights FILE [options]");
  cli.text("--weights", "FILE", &weights, "the flap network's weights YAML (required)")
      .integer("--starts", "N", &starts, {1, flapsim::kMaxEpisodes}, "held-out starts")
      .seed("--seed", "S", &seed, "their seed (flight_check's)")
      .real("--force", "N", &force, {0, 1e3}, "the push, N")
      .real("--step-size", "DT", &step, {1e-6, 0.1}, "s")
      .real("--after", "S", &after, {0, 1e3}, "s flown after the push");
  try {
    cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    if (cli.help()) {
      std::printf("%s", cli.usage().c_str());
      return 0;
    }
    if (weights.empty()) throw flapsim::InputError("--weights FILE is required");
    flapsim::ControllerSpec spec = flapsim::loadControllerYaml(weights);
    spec.params.roll_reflex_bank = 0.0;  // the network's own authority
    const auto model = flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(1, "afc"), "afc1");
    flapsim::FlightCheckParams check;  // flight_check's starts, with the push
    check.starts = starts;
    check.seed = seed;
    check.max_roll = check.max_pitch = 0.52;
    check.step_size = step;
    check.gust_force = force;
    check.gust_time = 0.2;
    const flapsim::EpisodeParams e = flapsim::flightCheckEpisodes(check);
    const std::vector<flapsim::EpisodeStart> drawn = flapsim::episodeStarts(e, model.get());
    const AnnWingController net(flapsim::FlapUnitController(spec.params, spec.weights));
    const double period = spec.params.control_period;
    const StrokeCommand stroke = net.commands(FlapSensing({flapsim::Quat::Identity()}))[0];
    int net_flips = 0, saved = 0;
    for (size_t i = 0; i < drawn.size(); ++i) {
      const flapsim::EpisodeStart& s = drawn[i];
      flapsim::EpisodeParams run = e;
      run.duration = s.force_time + after;
      run.flip_penalty = 1.0;  // a flip ends the flight
      PushOracle alone(net, period);
      const flapsim::EpisodeResult base = flapsim::runEpisode(model, alone, period, run, s);
      net_flips += base.flipped;
      const bool up = s.force_sign * force > 0.0;
      const bool left_pushed = s.force_link.find("left") != std::string::npos;
      const Patterns p = tryPatterns(model, net, period, run, s, stroke, up, left_pushed);
      saved += p.upright > 0;
      std::printf(
          "%2zu %-17s %-4s at %5.2f s | net alone: %-7s lowest up %6.3f | oracle: %2d/%d "
          "upright, best lowest up %.3f (%s)\n",
          i, s.force_link.c_str(), up ? "up" : "down", s.force_time,
          base.flipped ? "flips" : "upright", base.min_upright, p.upright, p.tried, p.best_up,
          p.best);
    }
    std::printf(
        "the network alone flips %d of %zu starts within %g s of the push; some oracle pattern "
        "keeps %d upright\n",
        net_flips, drawn.size(), after, saved);
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "push_oracle: %s\n", ex.what());
    return 2;
  }
  return 0;
}
