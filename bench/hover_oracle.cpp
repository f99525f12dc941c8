// hover_oracle: how much roll authority the hover creature's wings have against one of real
// air's impulses. Prints figures; never passes or fails.
//
//   hover_oracle [--gains FILE] [--urdf FILE] [--impulse torque|push] [--fraction 1]
//                [--starts 10] [--seed 2024] [--step-size 0.001] [--after 3] [--threads 2]
//
// flight_check --hover --real-air's held-out starts (within 0.1 rad, holding 5 m, the rest of
// real air as it is: wind, light turbulence, sensor noise and gyro bias) with one impulse, real
// air's (0.5 x weight x half-span for 0.5 s, or 4 x weight on a drawn wing for 0.2 s) times
// --fraction, each flown until --after s past the impulse's end: first under the controller alone,
// then with an oracle that knows when the impulse comes and adds a feed-forward roll share r to the
// controller's strokes over it: one wing's amplitude (and its stroke rates, the frequency kept)
// times 1 + r, the other's times 1 - r, each within max_stroke; r of 0.1, 0.2, 0.3, 0.45 or
// 0.6; either wing the stronger (the oracle tries both, so it needs no sign); both wings' frequency
// as commanded or 1.3 times it; from 0 or 0.05 s before the impulse to 0 or 0.1 s after its end:
// 80 patterns, the controller's own feedback acting throughout. Per start: whether the controller
// alone turns over, how many patterns keep it upright, and the best pattern's lowest up-component.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "flapsim/cli_args.h"
#include "flapsim/flight_check.h"
#include "flapsim/make_creature.h"

namespace {

using flapsim::StrokeCommand;

// One feed-forward pattern: the stronger wing (0 left, 1 right), the roll share, and the
// window around the impulse.
struct Pattern {
  int strong = 0;
  double share = 0.1, lead = 0.0, tail = 0.0;
  double faster = 1.0;  // both wings' frequency times this
};

std::vector<Pattern> patterns() {
  std::vector<Pattern> out;
  for (int strong : {0, 1}) {
    for (double share : {0.1, 0.2, 0.3, 0.45, 0.6}) {
      for (double lead : {0.0, 0.05}) {
        for (double tail : {0.0, 0.1}) {
          for (double faster : {1.0, 1.3}) {
            out.push_back(Pattern{strong, share, lead, tail, faster});
          }
        }
      }
    }
  }
  return out;
}

// `c` with its amplitude times `factor` (within `max_stroke` about its offset, as the controller
// keeps it) and its rates with it, its frequency times `faster`.
void scaleStroke(StrokeCommand& c, double factor, double faster, double max_stroke) {
  const double amplitude = std::min(c.amplitude * factor, max_stroke - std::abs(c.offset));
  const double k = c.amplitude > 0.0 ? amplitude / c.amplitude : 0.0;
  c.amplitude = amplitude;
  c.downstroke_rate *= k * faster;
  c.upstroke_rate *= k * faster;
}

// The impulse flown: which, how long it lasts, and how long the flights go on after it.
struct Impulse {
  bool torque = true;
  double lasts = 0.5, after = 3.0;
  double time(const flapsim::EpisodeStart& s) const {
    return torque ? s.torque_time : s.force_time;
  }
  // Ends the flight `after` s past the impulse's end (its figures from t = 0: the oracle reads
  // only whether it turned over and its lowest up-component, which count from the start).
  void shorten(const flapsim::EpisodeStart& s, flapsim::HoverFlightParams& f) const {
    f.duration = std::min(f.duration, time(s) + lasts + after);
    f.settle = 0.0;
  }
};

// Per start: how many patterns keep it upright, the best lowest up-component and its pattern.
struct Outcome {
  int kept = 0;
  double best = -2.0;
  std::string best_name;
};

std::vector<Outcome> tryPatterns(const flapsim::CreatureModelPtr& model,
                                 const flapsim::FlightCheckOptions& o, const Impulse& impulse) {
  const flapsim::HoverControllerParams g = flapsim::hoverCheckController(o);
  std::vector<Outcome> out(static_cast<size_t>(o.params.starts));
  for (const Pattern& pat : patterns()) {
    const std::vector<flapsim::HoverCheckRun> runs = flapsim::hoverRealAirCheck(
        model, o, [&](const flapsim::EpisodeStart& s, flapsim::HoverFlightParams& f) {
          impulse.shorten(s, f);
          const double t0 = impulse.time(s) - pat.lead;
          const double t1 = impulse.time(s) + impulse.lasts + pat.tail;
          f.override_strokes = [&g, pat, t0, t1](double t, std::array<StrokeCommand, 2>& strokes) {
            if (t < t0 || t >= t1) return;
            scaleStroke(strokes[pat.strong], 1.0 + pat.share, pat.faster, g.max_stroke);
            scaleStroke(strokes[1 - pat.strong], 1.0 - pat.share, pat.faster, g.max_stroke);
          };
        });
    for (size_t i = 0; i < runs.size(); ++i) {
      const flapsim::HoverFlightResult& r = runs[i].flight;
      out[i].kept += !r.flipped;
      if (r.lowest_upright <= out[i].best) continue;
      out[i].best = r.lowest_upright;
      char name[128];
      std::snprintf(name, sizeof name,
                    "%s wing stronger by %.2f, frequency x %.1f, %.2f s before to %.1f s after",
                    pat.strong == 0 ? "left" : "right", pat.share, pat.faster, pat.lead, pat.tail);
      out[i].best_name = name;
    }
  }
  return out;
}

// The flights: the hover_impulses table's (flight_check --hover --real-air --altitude 5 --roll
// 0.1 --pitch 0.1 --duration 30), with only `impulse`, `fraction` of real air's on `model`.
void setFlights(flapsim::FlightCheckParams& p, const Impulse& impulse, double fraction,
                const flapsim::CreatureModel& model) {
  const flapsim::RealAirImpulses real = flapsim::realAirImpulses(model);
  p.real_air = true;
  p.altitude = 5.0;
  p.max_roll = p.max_pitch = 0.1;
  p.duration = 30.0;
  p.real_air_torque = impulse.torque ? fraction * real.torque : 0.0;
  p.real_air_force = impulse.torque ? 0.0 : fraction * real.force;
}

}  // namespace

int main(int argc, char** argv) {
  flapsim::FlightCheckOptions o;
  o.hover = true;
  o.params.starts = 10;
  o.params.threads = 2;
  std::string name = "torque";
  Impulse impulse;
  double fraction = 1.0;
  flapsim::CliParser cli("usage: hover_oracle [options]");
  cli.text("--gains", "FILE", &o.gains, "the hover controller's gains (default: by hand)")
      .text("--urdf", "FILE", &o.urdf, "the creature (default: make_creature --layout hover)")
      .text("--impulse", "NAME", &name, "torque or push")
      .real("--fraction", "F", &fraction, {0, 1e3}, "its size, a fraction of real air's")
      .integer("--starts", "N", &o.params.starts, {1, flapsim::kMaxEpisodes}, "held-out starts")
      .seed("--seed", "S", &o.params.seed, "their seed (flight_check's)")
      .real("--step-size", "DT", &o.params.step_size, {1e-6, 0.1}, "s")
      .integer("--threads", "N", &o.params.threads, {1, 256},
               "threads (results do not depend on it)")
      .real("--after", "S", &impulse.after, {0, 1e3}, "s flown after the impulse's end");
  try {
    cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    if (cli.help()) {
      std::printf("%s", cli.usage().c_str());
      return 0;
    }
    if (name != "torque" && name != "push") {
      throw flapsim::InputError("--impulse must be torque or push, got '" + name + "'");
    }
    impulse.torque = name == "torque";
    const flapsim::CreatureModelPtr model =
        o.urdf.empty() ? flapsim::parseCreatureModel(flapsim::makeHoverUrdf("hover"),
                                                     "make_creature --layout hover")
                       : flapsim::loadCreatureModel(o.urdf);
    setFlights(o.params, impulse, fraction, *model);
    const flapsim::EpisodeParams flown =
        flapsim::flightCheckEpisodes(flapsim::realAirParams(o.params, *model));
    impulse.lasts = impulse.torque ? flown.gust_torque_duration : flown.gust_force_duration;
    const std::vector<flapsim::HoverCheckRun> alone = flapsim::hoverRealAirCheck(
        model, o, [&](const flapsim::EpisodeStart& s, flapsim::HoverFlightParams& f) {
          impulse.shorten(s, f);
        });
    const std::vector<Outcome> oracle = tryPatterns(model, o, impulse);
    const size_t tried = patterns().size();
    int flips = 0, saved = 0;
    for (size_t i = 0; i < alone.size(); ++i) {
      const flapsim::EpisodeStart& s = alone[i].start;
      flips += alone[i].flight.flipped;
      saved += oracle[i].kept > 0;
      std::printf(
          "%2zu %-6s at %5.2f s | alone: %-10s lowest up %6.3f | oracle: %2d/%zu upright, "
          "best lowest up %6.3f (%s)\n",
          i, impulse.torque ? "torque" : s.force_link.c_str(), impulse.time(s),
          alone[i].flight.flipped ? "turns over" : "upright", alone[i].flight.lowest_upright,
          oracle[i].kept, tried, oracle[i].best, oracle[i].best_name.c_str());
    }
    const flapsim::RealAirImpulses real = flapsim::realAirImpulses(*model);
    std::printf(
        "%s of %g %s (%g of real air's): the controller alone turns over in %d of %zu starts "
        "within %g s of its end; some oracle pattern keeps %d upright\n",
        name.c_str(), fraction * (impulse.torque ? real.torque : real.force),
        impulse.torque ? "N m for 0.5 s" : "N for 0.2 s", fraction, flips, alone.size(),
        impulse.after, saved);
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "hover_oracle: %s\n", ex.what());
    return 2;
  }
  return 0;
}
