// flapsim_bench: steps per second and real-time factor of the core world, per creature.
// Prints figures; never passes or fails on time.
//
//   flapsim_bench [--runs 5] [--seconds 2] [--only NAME] [--json] [--step S] [--turn-substep S]
//   flapsim_bench --check T [--reference-step S] [--only NAME | --urdf FILE [--height Z]]
//   flapsim_bench --urdf FILE [--height Z] [--no-ground] [--skip S] [--runs N] [--seconds S]
//   flapsim_bench --energy [--urdf FILE] [--seconds S] [--added-mass-products NAME]
//                          [--motor-work transmitted|servo]
//
// A flag the form given does not read is refused by name (flapsim_bench::unreadFlag).
//
// --step S, --turn-substep S: the world's step and turn substep, s (WorldParams' 1 ms and
// 0.5 ms by default; either form). --check T: instead of timing,
// the stability probe that bench/mujoco_bench.cpp applies to MuJoCo, here to flapsim at that
// step: T simulated seconds (not timed) of each creature at the step and at the reference step
// (--reference-step, 1/16 ms); a step counts if flapsim warned of nothing (no divergence),
// every speed stayed finite, the largest speed (root
// linear and angular, joints) within twice the reference's and the root's height change after
// 3 s within 10% of the reference's (of 1 m if that is more). Then "verdict: stable" or
// "verdict: UNSTABLE (why)". With --urdf, of that creature.
//
// The second form times one creature from a URDF, every wing stroking at 30/10 rad/s with
// amplitude 0.8, from `height`, after `skip` simulated seconds: the scenario of
// bench/node_rtf.py, so the node and the core are timed on the same stretch of flight.
#include "flapsim_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "bench_common.h"
#include "flapsim/make_creature.h"
#include "flapsim/world.h"
#include "fluid/surface.h"

namespace flapsim_bench {

std::string urdfPath(const std::string& file) {
  const std::string source = std::string(FLAPSIM_SOURCE_DIR) + "/urdf/" + file;
  if (std::ifstream(source).good()) return source;
  return std::string(FLAPSIM_SHARE_DIR) + "/urdf/" + file;
}

}  // namespace flapsim_bench

namespace {

using flapsim::CreatureModelPtr;
using flapsim::Pose;
using flapsim::Quat;
using flapsim::StrokeCommand;
using flapsim::Twist;
using flapsim::Vec3;
using flapsim::World;
using flapsim::WorldParams;
using flapsim_bench::benchSeconds;
using flapsim_bench::cpuTimeClock;
using flapsim_bench::median;
using flapsim_bench::urdfPath;

struct Scenario {
  std::string name;
  std::function<void(World&)> setup;
  int bodies = 0;
  int cells = 0;  // air cells at the world's default grid
};

// Air cells of a creature's aero links at the default air parameters (what the air model
// sums over each step, advancing faces only): of every shape, meshes, cylinders and spheres
// included.
int airCells(const flapsim::CreatureModel& model) {
  int cells = 0;
  for (size_t k = 0; k < model.links.size(); ++k) {
    const flapsim::LinkModel& l = model.links[k];
    if (!l.aero.enabled) continue;
    cells += static_cast<int>(
        flapsim::linkAeroSurface(model, static_cast<int>(k), flapsim::AirParams()).cells.size());
  }
  return cells;
}

Scenario flapper(const std::string& name, int pairs) {
  CreatureModelPtr model = flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(pairs, name));
  Scenario s{name, nullptr, static_cast<int>(model->links.size()), airCells(*model)};
  s.setup = [model](World& w) {
    w.spawn("c", model, Pose{Vec3(0, 0, 50), Quat::Identity()});
    w.setWingCommands("c", {},
                      std::vector<StrokeCommand>(model->wing_joints.size(), {30.0, 10.0, 0.8}));
  };
  return s;
}

Scenario fromUrdf(const std::string& file, double height) {
  CreatureModelPtr model = flapsim::loadCreatureModel(file);
  std::string name = file.substr(file.find_last_of('/') + 1);
  Scenario s{name.substr(0, name.find('.')), nullptr, static_cast<int>(model->links.size()),
             airCells(*model)};
  s.setup = [model, height](World& w) {
    w.spawn("c", model, Pose{Vec3(0, 0, height), Quat::Identity()});
    w.setWingCommands("c", {},
                      std::vector<StrokeCommand>(model->wing_joints.size(), {30.0, 10.0, 0.8}));
  };
  return s;
}

std::vector<Scenario> scenarios() {
  std::vector<Scenario> out;
  auto plate = flapsim::loadCreatureModel(urdfPath("plate.urdf"));
  out.push_back(
      {"plate",
       [plate](World& w) {
         w.spawn("c", plate, Pose{Vec3(0, 0, 50), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY()))});
       },
       1, airCells(*plate)});
  auto copter = flapsim::loadCreatureModel(urdfPath("bamboo_copter.urdf"));
  out.push_back({"bamboo_copter",
                 [copter](World& w) {
                   Twist spin;
                   spin.angular = Vec3(0, 0, 150);
                   w.spawn("c", copter, Pose{Vec3(0, 0, 50), Quat::Identity()}, spin);
                 },
                 3, airCells(*copter)});
  for (const flapsim_bench::BenchCreature& c : flapsim_bench::benchCreatures()) {
    out.push_back(flapper(c.name, c.units));
  }
  return out;
}

// Resident set size of this process, MB (Linux).
double residentMb() {
  FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0.0;
  char line[256];
  double kb = 0.0;
  while (std::fgets(line, sizeof(line), f)) {
    if (std::sscanf(line, "VmRSS: %lf kB", &kb) == 1) break;
  }
  std::fclose(f);
  return kb / 1024.0;
}

// Steps per second of one run of `steps` steps, after `skip` untimed ones; with `power`, the
// creature's motor power over the whole run.
double timeRun(const Scenario& s, bool air, int steps, WorldParams p = WorldParams(), int skip = 0,
               flapsim::CreaturePower* power = nullptr) {
  p.air.enabled = air;
  World w(p);
  s.setup(w);
  w.step(skip);
  const double t0 = benchSeconds();
  w.step(steps);
  const double sps = steps / (benchSeconds() - t0);
  if (power) *power = w.power("c");
  return sps;
}

// --check, as mujoco_bench's: when heights are compared, and the reference's step.
constexpr double kHeightTime = 3.0;           // s
constexpr double kReferenceStep = 0.0000625;  // s

struct Probe {
  int warnings = 0;  // divergences
  bool finite = true;
  double max_speed = 0.0, max_time = 0.0;  // the largest |root velocity| or |joint velocity|
  double early_height = 0.0, early_time = 0.0, end_height = 0.0;  // root, change since start
};

Probe probe(const Scenario& s, WorldParams p, double step, double seconds) {
  p.step_size = step;
  World w(p);
  s.setup(w);
  Probe r;
  const double z0 = w.state("c").link_poses[0].position.z();
  const int steps = static_cast<int>(std::lround(seconds / step));
  const int early = std::min(steps, static_cast<int>(std::lround(kHeightTime / step)));
  for (int i = 1; i <= steps; ++i) {
    w.step(1);
    if (w.divergence("c")) {
      ++r.warnings;
      break;
    }
    const flapsim::CreatureState c = w.state("c");
    const flapsim::Twist& root = c.link_twists[0];
    std::vector<double> speeds = c.joint_velocities;
    for (int k = 0; k < 3; ++k) {
      speeds.push_back(root.linear[k]);
      speeds.push_back(root.angular[k]);
    }
    for (double v : speeds) {
      if (!std::isfinite(v)) r.finite = false;
      if (std::abs(v) > r.max_speed) r.max_speed = std::abs(v), r.max_time = w.time();
    }
    r.end_height = c.link_poses[0].position.z() - z0;
    if (i == early) r.early_height = r.end_height, r.early_time = w.time();
  }
  return r;
}

std::string instability(const Probe& r, const Probe& ref) {
  auto figures = [](const Probe& x) {
    return flapsim_bench::ProbeFigures{x.warnings, x.finite, x.max_speed, x.early_height};
  };
  return flapsim_bench::instability(figures(r), figures(ref), "warning(s)", "max speed");
}

void printProbe(const char* label, double step, const Probe& r) {
  std::printf(
      "  %-9s %-10s warnings %d, %s, max speed %.4g (at %.3f s), height change %.4f m after %g s "
      "(%.4f m at the end)\n",
      label, (std::to_string(step * 1e3).substr(0, 8) + " ms").c_str(), r.warnings,
      r.finite ? "finite" : "NON-FINITE", r.max_speed, r.max_time, r.early_height, r.early_time,
      r.end_height);
}

// The reference: the same world parameters (turn substeps too) at `reference_step`.
void check(const Scenario& s, const WorldParams& p, double seconds, double reference_step) {
  const double step = p.step_size;
  const Probe at = probe(s, p, step, seconds);
  const Probe against = probe(s, p, reference_step, seconds);
  std::printf("%s, %g s simulated:\n", s.name.c_str(), seconds);
  printProbe("setting", step, at);
  printProbe("reference", reference_step, against);
  // The verdict allows 10% of 1 m when the reference changes height by less (as mujoco_bench's);
  // the error relative to the reference's own change, apart.
  const double error = std::abs(at.early_height - against.early_height);
  std::printf("  height error %.4f m, %.1f%% of the reference's change\n", error,
              100.0 * error / std::max(1e-12, std::abs(against.early_height)));
  const std::string why = instability(at, against);
  std::printf("  verdict: %s%s%s\n", why.empty() ? "stable" : "UNSTABLE (", why.c_str(),
              why.empty() ? "" : ")");
}

// The command line.
struct Options {
  int runs = 5;
  double seconds = 2.0;
  std::string only, urdf;
  double height = 50.0, skip = 0.0;
  bool json = false, ground = true, energy = false;
  flapsim::AddedMassProducts products = flapsim::AirParams().added_mass_products;
  flapsim::MotorWorkMeter motor_work = flapsim::MotorWorkMeter::kTransmitted;
  double step = WorldParams().step_size, check_seconds = 0.0, reference_step = kReferenceStep;
  double turn_substep = WorldParams().turn_substep;
  std::vector<std::string> given;  // the flags, in order
};

// Reads the command line into `o`: -1 to go on, else the exit code (a bad duration said on
// stderr).
int parseArgs(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    o.given.push_back(a);
    if (a == "--runs" && i + 1 < argc) {
      o.runs = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--seconds" && i + 1 < argc) {
      o.seconds = std::atof(argv[++i]);
    } else if (a == "--only" && i + 1 < argc) {
      o.only = argv[++i];
    } else if (a == "--cpu-time") {
      cpuTimeClock() = true;
    } else if (a == "--json") {
      o.json = true;
    } else if (a == "--energy") {
      o.energy = true;
    } else if (a == "--added-mass-products" && i + 1 < argc) {
      if (!flapsim_bench::parseAddedMassProducts(argv[++i], &o.products)) return 2;
    } else if (a == "--motor-work" && i + 1 < argc) {
      if (!flapsim_bench::parseMotorWork(argv[++i], &o.motor_work)) return 2;
    } else if (a == "--urdf" && i + 1 < argc) {
      o.urdf = argv[++i];
    } else if (a == "--height" && i + 1 < argc) {
      o.height = std::atof(argv[++i]);
    } else if (a == "--skip" && i + 1 < argc) {
      o.skip = std::atof(argv[++i]);
    } else if (a == "--no-ground") {
      o.ground = false;
    } else if ((a == "--step" || a == "--turn-substep" || a == "--check" ||
                a == "--reference-step") &&
               i + 1 < argc) {
      double* out = a == "--step"           ? &o.step
                    : a == "--turn-substep" ? &o.turn_substep
                    : a == "--check"        ? &o.check_seconds
                                            : &o.reference_step;
      // A turn substep of 0 is allowed: no substeps.
      const bool zero = a == "--turn-substep" && std::string(argv[i + 1]) == "0";
      if (zero) {
        *out = 0.0;
      } else if (!flapsim_bench::parseSeconds(argv[i + 1], out)) {
        std::fprintf(stderr, "flapsim_bench: %s wants a duration in (0, 1e5] s%s, not '%s'\n",
                     a.c_str(), a == "--turn-substep" ? " or 0" : "", argv[i + 1]);
        return 2;
      }
      ++i;
    } else {
      return flapsim_bench::usage(a == "--help" || a == "-h");  // asked: on stdout, exit 0
    }
  }
  return -1;
}

// --check: the probe of every scenario (--only's), or of the --urdf creature. The exit code.
int checkScenarios(const Options& o, const WorldParams& at_step) {
  try {
    for (const Scenario& s :
         o.urdf.empty() ? scenarios() : std::vector{fromUrdf(o.urdf, o.height)}) {
      if (o.only.empty() || s.name == o.only || !o.urdf.empty()) {
        check(s, at_step, o.check_seconds, o.reference_step);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "flapsim_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}

// The second form: the --urdf creature's motor power and rate, after --skip s. The exit code.
int timeUrdf(const Options& o, const WorldParams& at_step, int steps) {
  const double dt = o.step;
  Scenario s;
  try {
    s = fromUrdf(o.urdf, o.height);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "flapsim_bench: %s\n", e.what());
    return 1;
  }
  WorldParams p = at_step;
  std::vector<double> sps;
  flapsim::CreaturePower power;
  for (int r = 0; r < o.runs; ++r) {
    sps.push_back(timeRun(s, true, steps, p, static_cast<int>(std::lround(o.skip / dt)), &power));
  }
  // The rate's line last, its real-time factor the last word (bench/node_rtf.py reads it).
  std::printf("%s: motors %.3f W positive (%.0f W/kg), %.3f W net over its %g s\n", s.name.c_str(),
              power.meanPositivePower(), power.meanPositivePower() / power.mass,
              power.totalWork() / power.time, power.time);
  std::printf(
      "%s: %d bodies, %d air cells, %g s simulated after %g s: %.0f steps/s, real-time factor "
      "%.1f\n",
      s.name.c_str(), s.bodies, s.cells, steps * dt, o.skip, median(sps), median(sps) * dt);
  return 0;
}

// The table: each scenario (--only's) with and without air, and its motors' power.
void timeScenarios(const Options& o, const WorldParams& at_step, int steps) {
  const double dt = o.step;
  if (!o.json) {
    std::printf("flapsim_bench: %d runs of %g s simulated (%d steps of %g ms), medians\n", o.runs,
                o.seconds, steps, dt * 1e3);
    std::printf("%-14s %7s %14s %10s %10s %12s %9s %8s %10s\n", "creature", "bodies", "steps/s",
                "RTF", "air share", "us/body/step", "P+ (W)", "W/kg", "air cells");
  } else {
    std::printf("{\n  \"step_size\": %g,\n  \"runs\": %d,\n  \"steps\": %d,\n  \"creatures\": [\n",
                dt, o.runs, steps);
  }
  bool first = true;
  for (const Scenario& s : scenarios()) {
    if (!o.only.empty() && s.name != o.only) continue;
    std::vector<double> with_air, without_air;
    flapsim::CreaturePower power;  // of the motors, in air (the same in every run)
    for (int r = 0; r < o.runs; ++r) {
      with_air.push_back(timeRun(s, true, steps, at_step, 0, &power));
      without_air.push_back(timeRun(s, false, steps, at_step));
    }
    const double positive = power.meanPositivePower();
    const double sps = median(with_air);
    const double share = std::max(0.0, 1.0 - sps / median(without_air));
    const double per_body = 1e6 / (sps * s.bodies);  // flat when the cost is linear
    if (o.json) {
      std::printf(
          "%s    {\"creature\": \"%s\", \"bodies\": %d, \"steps_per_second\": %.0f, "
          "\"real_time_factor\": %.2f, \"air_share\": %.3f, \"us_per_body_step\": %.3f, "
          "\"positive_power_w\": %.4f, \"positive_power_w_per_kg\": %.1f, \"air_cells\": %d}",
          first ? "" : ",\n", s.name.c_str(), s.bodies, sps, sps * dt, share, per_body, positive,
          positive / power.mass, s.cells);
    } else {
      std::printf("%-14s %7d %14.0f %10.1f %9.1f%% %12.3f %9.3f %8.0f %10d\n", s.name.c_str(),
                  s.bodies, sps, sps * dt, 100.0 * share, per_body, positive, positive / power.mass,
                  s.cells);
    }
    first = false;
  }
  if (o.json) std::printf("\n  ]%s\n", o.only.empty() ? "," : "\n}");
}

// Finer air grid: the flap unit with 8 x 8 cells per face instead of the default.
void timeGrid(const Options& o, const WorldParams& at_step, int steps) {
  const Scenario unit = flapper("flap_unit", 1);
  std::vector<double> fine, coarse;
  for (int r = 0; r < o.runs; ++r) {
    WorldParams p = at_step;
    coarse.push_back(timeRun(unit, true, steps, p));
    p.air.subdivisions_u = p.air.subdivisions_v = 8;
    fine.push_back(timeRun(unit, true, steps, p));
  }
  const double grid_cost = median(coarse) / median(fine);
  if (o.json) {
    std::printf("  \"grid_8x8_step_time_ratio\": %.3f,\n", grid_cost);
  } else {
    std::printf("grid: flap_unit step time x%.2f with 8x8 cells per face (vs %dx%d)\n", grid_cost,
                WorldParams().air.subdivisions_u, WorldParams().air.subdivisions_v);
  }
}

// A flock of 16 flap units in one world, on 1 and 2 threads.
void timeFlock(const Options& o, const WorldParams& at_step, int steps) {
  CreatureModelPtr model = flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(1, "unit"));
  auto flock = [&](int threads, flapsim::CreatureState* last) {
    WorldParams p = at_step;
    p.threads = threads;
    World w(p);
    for (int i = 0; i < 16; ++i) {
      const std::string name = "u" + std::to_string(i);
      w.spawn(name, model, Pose{Vec3(i % 4, i / 4, 50), Quat::Identity()});
      w.setWingCommands(name, {}, {{30.0 + i, 10.0, 0.8}, {30.0 + i, 10.0, 0.8}});
    }
    const auto t0 = std::chrono::steady_clock::now();
    w.step(steps);
    const auto t1 = std::chrono::steady_clock::now();
    if (last) *last = w.state("u15");
    return steps / std::chrono::duration<double>(t1 - t0).count();
  };
  std::vector<double> one, two;
  flapsim::CreatureState s1, s2;
  for (int r = 0; r < o.runs; ++r) {
    one.push_back(flock(1, &s1));
    two.push_back(flock(2, &s2));
  }
  const bool same = s1.link_poses[0].position == s2.link_poses[0].position &&
                    s1.joint_positions == s2.joint_positions;
  if (o.json) {
    std::printf(
        "  \"flock_16\": {\"steps_per_second_1_thread\": %.0f, \"steps_per_second_2_threads\": "
        "%.0f, \"speedup\": %.3f, \"identical\": %s},\n",
        median(one), median(two), median(two) / median(one), same ? "true" : "false");
  } else {
    std::printf("flock_16: %.0f steps/s on 1 thread, %.0f on 2 (x%.2f), results %s\n", median(one),
                median(two), median(two) / median(one), same ? "identical" : "DIFFERENT");
  }
}

// Memory: resident size before and after a 12-unit world ran.
void measureMemory(const Options& o, const WorldParams& at_step, int steps) {
  const double before = residentMb();
  WorldParams p = at_step;
  World w(p);
  flapper("chain_12", 12).setup(w);
  w.step(steps);
  if (o.json) {
    std::printf("  \"resident_mb_with_chain_12\": %.1f,\n  \"resident_mb_before\": %.1f\n}\n",
                residentMb(), before);
  } else {
    std::printf("memory: process %.1f MB resident with a 12-unit world (%.1f MB before it)\n",
                residentMb(), before);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  const int parsed = parseArgs(argc, argv, o);
  if (parsed >= 0) return parsed;
  const std::string unread =
      flapsim_bench::unreadFlag(o.given, o.energy, o.check_seconds > 0.0, !o.urdf.empty());
  if (!unread.empty()) {
    std::fprintf(stderr, "flapsim_bench: %s\n", unread.c_str());
    return 2;
  }
  WorldParams at_step;
  at_step.step_size = o.step;
  at_step.turn_substep = o.turn_substep;
  at_step.ground = o.ground;
  if (!flapsim::validateWorldParams(at_step).empty()) {
    std::fprintf(stderr, "flapsim_bench: %s\n", flapsim::validateWorldParams(at_step).c_str());
    return 2;
  }
  if (o.energy) {
    return flapsim_bench::energyTable(o.urdf, o.seconds, o.products, o.motor_work);
  }
  if (o.check_seconds > 0.0) return checkScenarios(o, at_step);
  const int steps = std::max(1, static_cast<int>(std::lround(o.seconds / o.step)));
  if (!o.urdf.empty()) return timeUrdf(o, at_step, steps);
  timeScenarios(o, at_step, steps);
  if (!o.only.empty()) return 0;
  timeGrid(o, at_step, steps);
  timeFlock(o, at_step, steps);
  measureMemory(o, at_step, steps);
  return 0;
}
