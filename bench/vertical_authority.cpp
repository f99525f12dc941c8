// vertical_authority: what holding an altitude in turbulence asks of a creature's climb and
// sink, and what the flap unit has. Prints figures; never passes or fails.
//
//   vertical_authority [--level light] [--height 5] [--wind 1] [--flights 40] [--duration 60]
//                      [--settle 10] [--pairs 1] [--wing-effort NM] [--max-upstroke-rate R]
//
// 1. The bound: an ideal controller that knows the vertical air speed w it is in and moves
//    against it at up to A m/s relative to the air (dz/dt = w - clamp(w + z / 0.5 s, -A, A)),
//    in the living Dryden field at rest in a steady wind (--flights realisations, seeds 0..N-1,
//    --duration s each, the altitude error's rms after --settle s), for A = 0.5 to 3 m/s: its
//    mean and largest rms over the flights. No creature with that authority can do better.
// 2. The flap unit's authority (make_creature --pairs 1, 8 N m wing motors; --pairs N: the
//    chain of N units, 2 N m motors; --wing-effort: another limit): open loop from level at
//    rest, every wing at one downstroke and upstroke rate, amplitude 1.2 rad, its root's mean
//    vertical speed over the whole strokes between 1 and 2.5 s (from the first wing's upward
//    zero crossing to its last), and the strokes' mean period. By 1 s each stroke climbs as
//    the one before it to 1 %; from 2.5-4 s on, open loop, the creature tips and the climb
//    falls away. A fixed window cuts a stroke, whose bob moves a 2 s mean by up to 0.2 m/s.
// 3. With --max-upstroke-rate R (a network whose upstroke is a second output, as every
//    shipped afc_1 controller's is since 5 December 2026): the same climb at the network's
//    extreme downstroke rates (20 and 60 rad/s) and upstrokes from 10 to R rad/s, the fastest
//    climb and sink among them, and the bound of 1. for that authority (climbing at up to the
//    one, sinking at up to the other).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "flapsim/cli_args.h"
#include "flapsim/creature_model.h"
#include "flapsim/make_creature.h"
#include "flapsim/turbulence.h"
#include "flapsim/world.h"

namespace {

struct Bound {
  double mean = 0.0, worst = 0.0;
};

// The turbulence, the flights and the rms window of the bound (1. above).
struct BoundAir {
  std::string level;
  double height, wind;
  int flights;
  double duration, settle;
};

// The bound of an ideal controller that climbs through the air at up to `climb` m/s and sinks
// at up to `sink`, in `air`.
Bound idealBound(double climb, double sink, const BoundAir& air) {
  const auto& [level, height, wind, flights, duration, settle] = air;
  const double dt = 0.001, gain = 1.0 / 0.5;
  Bound b;
  for (int seed = 0; seed < flights; ++seed) {
    flapsim::TurbulenceParams p;
    p.wind_at_6m = flapsim::turbulenceLevelWind(level);
    p.height = height;
    p.seed = static_cast<std::uint64_t>(seed);
    const flapsim::TurbulenceField field(p, flapsim::turbulenceSeed(p, "ideal"));
    double z = 0.0, square = 0.0;
    int samples = 0;
    const auto steps = static_cast<int>(std::lround(duration / dt));
    for (int i = 0; i < steps; ++i) {
      const double t = i * dt;
      const double w =
          field.velocity(flapsim::Vec3(0.0, 0.0, height), t, flapsim::Vec3(wind, 0.0, 0.0)).z();
      z += (w - std::clamp(w + gain * z, -climb, sink)) * dt;
      if (t >= settle) {
        square += z * z;
        ++samples;
      }
    }
    const double rms = std::sqrt(square / std::max(samples, 1));
    b.mean += rms / flights;
    b.worst = std::max(b.worst, rms);
  }
  return b;
}

// The root's mean vertical speed over the whole strokes from 1 to 2.5 s of a chain of `pairs`
// flap units of `unit`, open loop from level at rest, in the air whose added mass does
// `products` (AirParams::added_mass_products), and the strokes' mean period.
struct Climb {
  double speed = 0.0;   // m/s
  double period = 0.0;  // s
};

Climb openLoopClimb(int pairs, double downstroke, double upstroke,
                    flapsim::AddedMassProducts products, const flapsim::FlapUnitParams& unit) {
  flapsim::WorldParams p;
  p.ground = false;
  p.air.added_mass_products = products;
  flapsim::World world(p);
  const auto model = flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(pairs, "afc", unit),
                                                 "afc" + std::to_string(pairs));
  flapsim::Pose pose;
  pose.position = flapsim::Vec3(0.0, 0.0, 50.0);
  world.spawn("afc", model, pose);
  std::vector<std::string> joints;
  std::vector<flapsim::StrokeCommand> commands;
  for (int j : model->wing_joints) {
    joints.push_back(model->joints[j].name);
    flapsim::StrokeCommand c;
    c.downstroke_rate = downstroke;
    c.upstroke_rate = upstroke;
    c.amplitude = 1.2;
    commands.push_back(c);
  }
  world.setWingCommands("afc", joints, commands);
  const int wing = model->wing_joints.front();
  const double dt = world.params().step_size;
  const auto steps = static_cast<int>(std::lround(2.5 / dt));
  double last = world.state("afc").joint_positions[wing];
  int strokes = -1;
  double t0 = 0.0, z0 = 0.0, t1 = 0.0, z1 = 0.0;
  for (int i = 1; i <= steps; ++i) {
    world.step(1);
    const double q = world.state("afc").joint_positions[wing];
    if (last < 0.0 && q >= 0.0 && i * dt >= 1.0) {
      t1 = i * dt;
      z1 = world.rootPose("afc").position.z();
      if (++strokes == 0) t0 = t1, z0 = z1;
    }
    last = q;
  }
  if (strokes < 1) throw std::runtime_error("no whole stroke between 1 and 2.5 s");
  return Climb{(z1 - z0) / (t1 - t0), (t1 - t0) / strokes};
}

// 3.: the climb at downstrokes of 20 and 60 rad/s and upstrokes of 10 to `max_upstroke`, the
// fastest climb and sink among them and the bound for that authority.
void printUpstrokeAuthority(double max_upstroke, int pairs, flapsim::AddedMassProducts products,
                            const flapsim::FlapUnitParams& unit, const BoundAir& air) {
  std::printf("with the upstroke a second output up to %g rad/s:\n", max_upstroke);
  std::vector<double> upstrokes;
  for (double u = 10.0; u < max_upstroke; u += u < 30.0 ? 2.0 : 5.0) upstrokes.push_back(u);
  upstrokes.push_back(max_upstroke);
  double best_climb = -1e9, best_sink = 1e9;
  std::pair<double, double> climb_at, sink_at;
  for (double down : {20.0, 60.0}) {
    for (double up : upstrokes) {
      const Climb c = openLoopClimb(pairs, down, up, products, unit);
      std::printf("  %g / %g rad/s: %.2f m/s (period %.4f s)\n", down, up, c.speed, c.period);
      if (c.speed > best_climb) best_climb = c.speed, climb_at = {down, up};
      if (c.speed < best_sink) best_sink = c.speed, sink_at = {down, up};
    }
  }
  const Bound b = idealBound(std::max(best_climb, 0.0), std::max(-best_sink, 0.0), air);
  std::printf(
      "fastest climb %.2f m/s at %g / %g rad/s, fastest sink %.2f m/s at %g / %g rad/s; an "
      "ideal controller with that authority: altitude rms after %g s mean %.3f m, largest "
      "%.3f m of %d flights\n",
      best_climb, climb_at.first, climb_at.second, -best_sink, sink_at.first, sink_at.second,
      air.settle, b.mean, b.worst, air.flights);
}

}  // namespace

int main(int argc, char** argv) {
  std::string level = "light";
  double height = 5.0, wind = 1.0, duration = 60.0, settle = 10.0;
  int flights = 40, pairs = 1;
  double wing_effort = 0.0, max_upstroke = 0.0;
  std::string products = flapsim::addedMassProductsName(flapsim::AirParams().added_mass_products);
  flapsim::CliParser cli("usage: vertical_authority [options]");
  cli.text("--level", "LEVEL", &level, "turbulence: light, moderate or severe")
      .real("--height", "M", &height, {flapsim::kMinTurbulenceHeight, 300.0}, "m")
      .real("--wind", "W", &wind, {0, 20}, "the steady wind, m/s")
      .integer("--flights", "N", &flights, {1, 10000}, "realisations of the turbulence")
      .real("--duration", "S", &duration, {1, 3600}, "s each")
      .real("--settle", "S", &settle, {0, 3600}, "the rms counts after S s")
      .text("--added-mass-products", "NAME", &products,
            "the flap unit's air: what its plates' added mass does beyond -A dnu",
            flapsim::addedMassProductsNames())
      .integer("--pairs", "N", &pairs, {1, 24}, "the open-loop flier: a chain of N flap units")
      .real("--wing-effort", "NM", &wing_effort, {0, 1e6},
            "its wing motors' torque limit (0: make_creature's, 8 N m for one unit, 2 for a chain)")
      .real("--max-upstroke-rate", "R", &max_upstroke, {0, 200},
            "also the climb at downstrokes of 20 and 60 rad/s and upstrokes of 10 to R rad/s, "
            "and the bound for the fastest climb and sink among them (0: not)");
  try {
    cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    if (cli.help()) {
      std::printf("%s", cli.usage().c_str());
      return 0;
    }
    const BoundAir air{level, height, wind, flights, duration, settle};
    const flapsim::DrydenScales s =
        flapsim::drydenScales(flapsim::turbulenceLevelWind(level), height);
    std::printf(
        "%s turbulence at %g m in a %g m/s wind: sigma_w %.2f m/s, L_w %.1f m, T_L %.2f s; an "
        "ideal controller climbing or sinking at up to A m/s against the air's w, altitude "
        "rms after %g s of %g s over %d flights:\n",
        level.c_str(), height, wind, s.sigma.z(), s.length.z(), flapsim::lagrangianTime(s, height),
        settle, duration, flights);
    std::printf("A (m/s)  mean rms (m)  largest rms (m)\n");
    for (double a : {0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0}) {
      const Bound b = idealBound(a, a, air);
      std::printf("%7.2f  %12.3f  %15.3f\n", a, b.mean, b.worst);
    }
    flapsim::FlapUnitParams unit;
    if (wing_effort > 0.0) unit.wing_effort = wing_effort;
    std::printf(
        "%d flap unit(s) open loop (every wing alike, amplitude 1.2 rad, %g N m wing motors; the "
        "added mass's products %s), the root's mean vertical speed over the whole strokes "
        "between 1 and 2.5 s:\n",
        pairs, flapsim::wingEffort(unit, pairs), products.c_str());
    std::printf("downstroke  upstroke (rad/s)  climb (m/s)  stroke period (s)\n");
    for (const auto& r : std::vector<std::pair<double, double>>{
             {10, 10}, {20, 10}, {30, 10}, {40, 10}, {60, 10}, {80, 10}, {100, 10}}) {
      const Climb c =
          openLoopClimb(pairs, r.first, r.second, flapsim::parseAddedMassProducts(products), unit);
      std::printf("%10.0f  %16.0f  %11.2f  %17.4f\n", r.first, r.second, c.speed, c.period);
    }
    if (max_upstroke > 0.0) {
      printUpstrokeAuthority(max_upstroke, pairs, flapsim::parseAddedMassProducts(products), unit,
                             air);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vertical_authority: %s\n", e.what());
    return 2;
  }
}
