#include "flapsim/flight_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "evolution/evolve_flag_rules.h"
#include "flapsim/ann.h"
#include "flapsim/ga.h"
#include "flapsim/hover_gains.h"
#include "flapsim/world.h"

namespace flapsim {

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
  episode.world.turn_substep = p.turn_substep;
  episode.min_wind = episode.max_wind = p.wind;
  episode.gust_torque = p.gust_torque;
  episode.gust_force = p.gust_force;
  episode.gust_link = p.gust_link;
  episode.gust_torque_duration = episode.gust_force_duration = p.gust_time;
  if (p.real_air) {
    episode.gust_torque_duration = RealAirImpulses().torque_duration;
    episode.gust_force_duration = RealAirImpulses().force_duration;
  }
  episode.imu_noise.orientation = episode.imu_noise.angular_velocity = p.noise;
  episode.altitude_noise = p.altitude_noise;
  episode.velocity_noise = p.velocity_noise;
  episode.world.air.added_mass_products = p.added_mass_products;
  episode.world.motor_work = p.motor_work;
  episode.world.air.turbulence.wind_at_6m = p.turbulence;
  episode.gyro_bias = p.gyro_bias;
  episode.altitude_hold = p.altitude.has_value();
  if (p.altitude) episode.min_altitude = episode.max_altitude = *p.altitude;
  const std::string err = validateEpisodeParams(episode);
  if (!err.empty()) throw InputError("flight check: " + err);
  return episode;
}

CreatureState spawnedLevel(const CreatureModel& model) {
  WorldParams params;
  params.ground = false;
  params.air.enabled = false;
  World world(params);
  world.spawn("c", std::make_shared<CreatureModel>(model), Pose());
  return world.state("c");
}

double creatureSpan(const CreatureModel& model) {
  const CreatureState state = spawnedLevel(model);
  double low = 0.0, high = 0.0;
  for (size_t k = 0; k < model.links.size(); ++k) {
    const Pose link = model.links[k].fromUrdf(state.link_poses[k]);
    for (const Box& box : model.links[k].boxes) {
      for (int corner = 0; corner < 8; ++corner) {
        const Vec3 local(corner & 1 ? 0.5 : -0.5, corner & 2 ? 0.5 : -0.5, corner & 4 ? 0.5 : -0.5);
        const Vec3 at = link.position +
                        link.orientation * (box.origin.position +
                                            box.origin.orientation * local.cwiseProduct(box.size));
        low = std::min(low, at.y());
        high = std::max(high, at.y());
      }
    }
  }
  return high - low;
}

namespace {

// Real air's settings beside its impulses (realAirParams, setRealAirEpisodes).
constexpr double kRealAirWind = 1.0;  // m/s
constexpr const char* kRealAirTurbulence = "light";
constexpr double kRealAirImuNoise = 0.05;       // rad and rad/s
constexpr double kRealAirGyroBias = 0.02;       // rad/s
constexpr double kRealAirAltitudeNoise = 0.05;  // m

}  // namespace

RealAirImpulses realAirImpulses(const CreatureModel& model) {
  const double weight = model.totalMass() * 9.81;
  // The pushed wing's unit: a flap unit of a chain, or the whole of any other creature.
  const int units = model.findLink("unit0_body") >= 0 ? flapUnitLayout(model).units() : 1;
  RealAirImpulses i;
  i.torque = 0.5 * weight * 0.5 * creatureSpan(model);
  i.force = 4.0 * weight / units;
  return i;
}

FlightCheckParams realAirParams(FlightCheckParams p, const CreatureModel& model) {
  const RealAirImpulses i = realAirImpulses(model);
  p.wind = p.real_air_wind.value_or(kRealAirWind);
  p.turbulence = p.real_air_turbulence.value_or(turbulenceLevelWind(kRealAirTurbulence));
  p.gust_torque = p.real_air_torque.value_or(i.torque);
  p.gust_force = p.real_air_force.value_or(i.force);
  p.noise = kRealAirImuNoise;
  p.gyro_bias = kRealAirGyroBias;
  p.altitude_noise = kRealAirAltitudeNoise;
  return p;
}

void setRealAirEpisodes(EpisodeParams& e) {
  e.real_air = true;
  e.min_wind = e.max_wind = kRealAirWind;
  e.world.air.turbulence.wind_at_6m = turbulenceLevelWind(kRealAirTurbulence);
  e.imu_noise.orientation = e.imu_noise.angular_velocity = kRealAirImuNoise;
  e.gyro_bias = kRealAirGyroBias;
  e.altitude_noise = kRealAirAltitudeNoise;
}

EpisodeParams realAirGusts(EpisodeParams e, const CreatureModel& model) {
  const RealAirImpulses i = realAirImpulses(model);
  e.gust_torque = e.real_air_torque ? i.torque : 0.0;
  e.gust_torque_duration = i.torque_duration;
  e.gust_force = e.real_air_push ? i.force : 0.0;
  e.gust_force_duration = i.force_duration;
  return e;
}

std::vector<FlightCheckRun> flightCheck(const CreatureModelPtr& model,
                                        const ControllerSpec& controller,
                                        const FlightCheckParams& given) {
  if (given.threads < 1) throw InputError("flight check: threads must be >= 1");
  if (given.trace_start >= given.starts) {
    throw InputError("--trace: start " + std::to_string(given.trace_start) + " of " +
                     std::to_string(given.starts) + " (the starts are numbered from 0)");
  }
  const FlightCheckParams p = given.real_air ? realAirParams(given, *model) : given;
  const EpisodeParams episode = flightCheckEpisodes(p);
  // Roll uniform in +-max_roll (episodeStarts alternates the sign of |roll| in [0, max]).
  const std::vector<EpisodeStart> starts = episodeStarts(episode, model.get());
  const AnnWingController ann(FlapUnitController(controller.params, controller.weights));
  std::vector<FlightCheckRun> runs(starts.size());
  parallelMap(static_cast<int>(starts.size()), p.threads, [&](int i) {
    runs[i] = FlightCheckRun{runEpisode(model, ann, controller.params.control_period, episode,
                                        starts[i], i == p.trace_start),
                             starts[i]};
    return 0.0;
  });
  return runs;
}

std::string flightTraceCsv(const FlightCheckRun& run, const std::vector<std::string>& wing_joints) {
  if (run.trace.empty()) throw InputError("flight trace: the start was flown without a trace");
  std::ostringstream out;
  out << std::setprecision(10) << "time,height,upright,air_vz";
  for (const std::string& joint : wing_joints) out << "," << joint << "_down," << joint << "_up";
  out << "\n";
  for (const EpisodeSample& s : run.trace) {
    if (s.downstroke.size() != wing_joints.size() || s.upstroke.size() != wing_joints.size()) {
      throw InputError("flight trace: " + std::to_string(s.downstroke.size()) +
                       " wings commanded, " + std::to_string(wing_joints.size()) + " named");
    }
    out << s.time << "," << s.height << "," << s.upright << "," << s.air.z();
    for (size_t i = 0; i < wing_joints.size(); ++i) {
      out << "," << s.downstroke[i] << "," << s.upstroke[i];
    }
    out << "\n";
  }
  return out.str();
}

namespace {

// ", turbulence W20 7.72 m/s", or nothing without turbulence.
std::string turbulenceNote(double wind_at_6m) {
  if (wind_at_6m <= 0.0) return "";
  char note[64];
  std::snprintf(note, sizeof note, ", turbulence W20 %.2f m/s", wind_at_6m);
  return note;
}

// Tags of the flags that only one of flight_check's modes flies with, and of those of the
// held-out starts: the network's, and with --hover only real air's.
const char* const kNetworkOnly = "network";
const char* const kHoverOnly = "hover";
const char* const kStarts = "starts";

// The air's and the sensors' flags: wind, turbulence, gusts, noise, the real-air row.
void airAndSensorFlags(CliParser& t, FlightCheckParams& p) {
  t.real("--wind", "SPEED", &p.wind, {0, 1e3},
         "steady wind from t = 0, m/s, from a heading drawn per start (--hover: along +y)")
      .custom(
          "--turbulence", {"LEVEL"},
          [&p](const std::vector<std::string>& v) {
            p.turbulence = turbulenceWindFromFlag("--turbulence", v[0]);
          },
          [&p] { return formatCliNumber(p.turbulence) + " m/s at 6 m"; },
          "Dryden turbulence (MIL-F-8785C): none, light, moderate, severe or the wind at 6 m "
          "(m/s), frozen in the air and carried by --wind, a realisation per start (--hover: "
          "seed 0)")
      .real("--gyro-bias", "B", &p.gyro_bias, {0, 1e3},
            "a constant gyro bias per start, up to B rad/s, any direction")
      .tag(kNetworkOnly)
      .flag("--real-air", &p.real_air, true,
            "real air, all at once: wind 1 m/s, light turbulence, a roll torque (0.5 x weight x "
            "half-span) for 0.5 s and a push on a drawn wing (4 x its unit's weight) for 0.2 s "
            "at drawn times, IMU noise 0.05, a gyro bias up to 0.02 rad/s, altimeter noise "
            "0.05 m (--hover too: from held-out starts); --wind and --turbulence with it give "
            "its wind and turbulence instead")
      .real("--gust-torque", "NM", &p.gust_torque, {-1e6, 1e6},
            "a roll torque at a time drawn per start (10-60 % of the flight), sign drawn; with "
            "--real-air its size instead of real air's (0: none)")
      .tag(kNetworkOnly)
      .real("--gust-force", "N", &p.gust_force, {-1e6, 1e6},
            "a vertical push (> 0: up) on --gust-link at a time drawn per start; with "
            "--real-air its size instead of real air's (0: none)")
      .tag(kNetworkOnly)
      .text("--gust-link", "LINK", &p.gust_link,
            "the link pushed (default: a wing drawn per start, up or down)")
      .tag(kNetworkOnly)
      .real("--gust-time", "S", &p.gust_time, {0, kMaxEpisodeDuration, true},
            "how long each gust acts, s")
      .tag(kNetworkOnly)
      .real("--noise", "RAD", &p.noise, {0, 1e3},
            "IMU noise: orientation RAD rad, angular velocity RAD rad/s")
      .tag(kNetworkOnly)
      .real("--altitude-noise", "M", &p.altitude_noise, {0, 1e3}, "altimeter noise, m")
      .tag(kNetworkOnly)
      .real("--velocity-noise", "V", &p.velocity_noise, {0, 1e3},
            "ground-speed sensor noise, m/s per axis (read with ground-speed damping or a climb "
            "input)")
      .tag(kNetworkOnly);
  addedMassProductsFlag(t, &p.added_mass_products);
  motorWorkFlag(t, &p.motor_work,
                "unless --added-mass-products omitted: how the W/kg figures take the motors' work, "
                "transmitted (the default) or servo (WorldParams::motor_work)");
}

}  // namespace

CliParser flightCheckCli(FlightCheckOptions& o) {
  FlightCheckParams& p = o.params;
  CliParser t("usage: flight_check --weights FILE [options]");
  t.text("--weights", "FILE", &o.weights, "controller weights YAML (evolve's output; required)")
      .tag(kNetworkOnly)
      .integer("--pairs", "N", &o.pairs, {1, 1000}, "the creature: make_creature --pairs N, or")
      .tag(kNetworkOnly)
      .text("--urdf", "FILE", &o.urdf, "a creature of flap units from a URDF file")
      .integer("--starts", "N", &p.starts, {1, kMaxEpisodes}, "held-out starts")
      .tag(kStarts)
      .seed("--seed", "S", &p.seed, "their seed (it also draws headings, gust times, wings)")
      .tag(kStarts)
      .real("--roll", "R", &p.max_roll, {0, M_PI}, "start roll uniform in +-R rad")
      .real("--pitch", "P", &p.max_pitch, {0, M_PI}, "start pitch uniform in +-P rad")
      .real("--duration", "T", &p.duration, {0, kMaxEpisodeDuration, true}, "s")
      .real("--step-size", "DT", &p.step_size, {1e-6, 0.1}, "s")
      .custom(
          "--turn-substep", {"S"},
          [&p](const std::vector<std::string>& v) {
            p.turn_substep = turnSubstepFromFlag("--turn-substep", v[0]);
          },
          [&p] { return formatCliNumber(p.turn_substep); },
          "a step in which a wing turns is cut into pieces of at most S s (0: never)")
      .integer("--threads", "N", &p.threads, {1, 256},
               "parallel flights; results do not depend on it")
      .tag(kStarts)
      .flag("--hover", &o.hover, true,
            "fly the hover creature (make_creature --layout hover, or --urdf) under its "
            "controller instead, started --roll, --pitch tilted (0 unless given)")
      .text("--gains", "FILE", &o.gains,
            "--hover: the controller's gains file (evolve --preset hover's; default: by hand)")
      .tag(kHoverOnly)
      .text("--write-gains", "FILE", &o.write_gains, "--hover: write the gains flown to FILE")
      .tag(kHoverOnly)
      .custom(
          "--trace", {"N", "FILE"},
          [&o](const std::vector<std::string>& v) {
            o.params.trace_start = parseCliInteger("--trace", v[0], {0, kMaxEpisodes});
            o.trace_path = v[1];
          },
          [&o] {
            return o.trace_path.empty() ? std::string("none")
                                        : std::to_string(o.params.trace_start) + " " + o.trace_path;
          },
          "write start N's flight to FILE as CSV: each control update's time, the root's height "
          "and up-component, the air's vertical speed there, each wing's commanded downstroke and "
          "upstroke rates")
      .tag(kNetworkOnly);
  airAndSensorFlags(t, p);
  t.custom(
      "--altitude", {"M"},
      [&p](const std::vector<std::string>& v) {
        p.altitude = parseCliReal("--altitude", v[0], {-1e6, 1e6});
      },
      [&p] { return p.altitude ? formatCliNumber(*p.altitude) : std::string("climb"); },
      "hold M m (the root link frame's height); default: climb (--hover: 3)");
  return t;
}

void takeRealAirSizes(FlightCheckOptions& o, const std::vector<CliSeen>& seen) {
  FlightCheckParams& p = o.params;
  if (!p.real_air) return;
  for (const CliSeen& given : seen) {
    const std::string& name = given.flag->names[0];
    if (name == "--gust-torque") p.real_air_torque = p.gust_torque;
    if (name == "--gust-force") p.real_air_force = p.gust_force;
    if (name == "--wind") p.real_air_wind = p.wind;
    if (name == "--turbulence") p.real_air_turbulence = p.turbulence;
  }
}

std::string flightCheckUnusedFlag(const FlightCheckOptions& o, const std::vector<CliSeen>& seen) {
  for (const CliSeen& given : seen) {
    const std::string& name = given.flag->names[0];
    const FlightCheckParams& p = o.params;
    // With --real-air the two impulses' flags give their sizes (the hover's too).
    const bool real_air_size = p.real_air && (name == "--gust-torque" || name == "--gust-force");
    if (real_air_size && (name == "--gust-torque" ? p.gust_torque : p.gust_force) < 0.0) {
      return name + " with --real-air is a size (its sign is drawn): give it >= 0";
    }
    if (o.hover && ((given.flag->tag == kNetworkOnly && !real_air_size) ||
                    (given.flag->tag == kStarts && !p.real_air))) {
      return name +
             " has no effect with --hover (one flight of the hover controller: no network, "
             "no held-out starts, gusts or sensor noise but those of --real-air)";
    }
    if (!o.hover && given.flag->tag == kHoverOnly) {
      return name + " is for --hover only (the network's flights have no hover gains)";
    }
    // --wind and --turbulence with --real-air give its air (takeRealAirSizes); these it sets.
    for (const char* set :
         {"--gust-link", "--gust-time", "--noise", "--altitude-noise", "--gyro-bias"}) {
      if (p.real_air && name == set) return name + " is set by --real-air (give one or the other)";
    }
    if (name == "--gust-link" && p.gust_force == 0.0) {
      return name + " has no effect without --gust-force";
    }
    if (name == "--gust-time" && p.gust_force == 0.0 && p.gust_torque == 0.0) {
      return name + " has no effect without --gust-force or --gust-torque";
    }
    if (name == "--motor-work" && p.added_mass_products == AddedMassProducts::kOmitted) {
      return name + kMotorWorkWithoutProducts;
    }
  }
  return "";
}

std::string flightCheckUnusedSensorFlag(const FlapControllerParams& controller,
                                        const std::vector<CliSeen>& seen) {
  for (const CliSeen& given : seen) {
    const std::string& name = given.flag->names[0];
    if (name == "--altitude-noise" && !controller.altitude_input) {
      return name + " has no effect: the controller's network reads no altimeter";
    }
    if (name == "--velocity-noise" && controller.velocity_gain <= 0.0 && !controller.climb_input) {
      return name + " has no effect: the controller has no ground-speed damping or climb input";
    }
  }
  return "";
}

std::string realAirName(const FlightCheckParams& p) {
  std::string name = "real air";
  if (p.real_air_wind) {
    char wind[64];
    std::snprintf(wind, sizeof wind, ", wind %g m/s", *p.real_air_wind);
    name += wind;
  }
  if (p.real_air_turbulence) {
    name += *p.real_air_turbulence > 0.0 ? turbulenceNote(*p.real_air_turbulence)
                                         : std::string(", no turbulence");
  }
  return name;
}

std::string flightCheckReport(const FlightCheckOptions& o, const std::vector<FlightCheckRun>& runs,
                              int wing_pairs, int& failed) {
  const FlightCheckParams& p = o.params;
  constexpr double kDeg = 180.0 / M_PI;
  char line[400];
  std::snprintf(line, sizeof line,
                "%-5s %7s %7s %9s %7s %6s %8s %8s %7s %8s %6s %8s %7s %8s %9s %8s %6s\n", "start",
                "roll", "pitch", "wind", "flipped", "min_up", "final_z", "min_z", "upright",
                "alt_rms", "up_set", "drift", "bank", "P+", "P+/m", "P_net", "result");
  std::string out = line;
  failed = 0;
  for (size_t i = 0; i < runs.size(); ++i) {
    const FlightCheckRun& r = runs[i];
    const bool ok = r.passed(p.start_height);
    failed += ok ? 0 : 1;
    const Vec3& w = r.start.wind;
    char wind[32] = "-";
    if (w.norm() > 0.0) {
      std::snprintf(wind, sizeof wind, "%.1f@%.0f°", w.norm(), std::atan2(w.y(), w.x()) * kDeg);
    }
    char rms[16] = "-";
    if (std::isfinite(r.altitude_rms)) std::snprintf(rms, sizeof rms, "%.3fm", r.altitude_rms);
    std::snprintf(line, sizeof line,
                  "%-5zu %6.1f° %6.1f° %9s %7s %6.3f %7.2fm %7.2fm %6.1f%% %8s %6.3f %7.2fm "
                  "%6.2f° %7.2fW %5.0fW/kg %7.2fW %6s\n",
                  i, r.start.roll * kDeg, r.start.pitch * kDeg, wind, r.flipped ? "yes" : "no",
                  r.min_upright, r.final_height, r.min_height, 100.0 * r.upright_fraction, rms,
                  r.min_upright_settled, r.lateral_drift, r.mean_bank * kDeg, r.positive_power,
                  r.mass > 0.0 ? r.positive_power / r.mass : 0.0, r.net_power,
                  ok ? "pass" : "FAIL");
    out += line;
  }
  std::snprintf(line, sizeof line, "%d of %zu starts passed (",
                static_cast<int>(runs.size()) - failed, runs.size());
  out += line + o.weights;
  const std::string air = p.real_air ? ", " + realAirName(p) : turbulenceNote(p.turbulence);
  std::snprintf(line, sizeof line, ", %g s at %g ms, %d wing pair(s)%s)\n", p.duration,
                1000.0 * p.step_size, wing_pairs, air.c_str());
  return out + line;
}

std::string flightPowerSummary(const std::vector<FlightCheckRun>& runs, double disk_area) {
  double positive = 0.0, net = 0.0, mass = 0.0;
  for (const FlightCheckRun& r : runs) {
    positive += r.positive_power / static_cast<double>(runs.size());
    net += r.net_power / static_cast<double>(runs.size());
    mass = r.mass;
  }
  const double ideal = idealHoverPower(9.81 * mass, 1.204, disk_area);
  char line[320];
  std::snprintf(line, sizeof line,
                "mechanical power of the motors, mean over the starts: %.2f W positive (%.0f W/kg "
                "of its %.1f g), %.2f W net; figure of merit %.3f (ideal %.3f W on a disk of %.3f "
                "m^2)\n",
                positive, mass > 0.0 ? positive / mass : 0.0, 1000.0 * mass, net,
                positive > 0.0 ? ideal / positive : 0.0, ideal, disk_area);
  return line;
}

HoverControllerParams hoverCheckController(const FlightCheckOptions& o) {
  HoverControllerParams controller;
  if (!o.gains.empty()) controller = loadHoverGainsYaml(o.gains);
  controller.altitude = o.params.altitude.value_or(3.0);
  return controller;
}

std::string hoverCheckGainsFile(const FlightCheckOptions& o) {
  const std::string from =
      o.gains.empty() ? "set by hand (flapsim::HoverControllerParams' defaults), not evolved"
                      : "as read from " + o.gains;
  return hoverGainsToYaml(hoverCheckController(o),
                          "Hover controller gains " + from +
                              ".\nReproduce: flight_check --hover --write-gains FILE" +
                              (o.gains.empty() ? "" : " --gains " + o.gains));
}

std::string hoverCheckReport(const CreatureModelPtr& model, const FlightCheckOptions& o, bool& ok) {
  const HoverControllerParams controller = hoverCheckController(o);
  const double altitude = controller.altitude;
  HoverFlightParams p;
  p.duration = o.params.duration;
  p.world.step_size = o.params.step_size;
  p.world.turn_substep = o.params.turn_substep;
  p.world.air.wind = Vec3(0.0, o.params.wind, 0.0);
  p.world.air.added_mass_products = o.params.added_mass_products;
  p.world.motor_work = o.params.motor_work;
  p.world.air.turbulence.wind_at_6m = o.params.turbulence;
  p.world.air.turbulence.height = std::clamp(altitude, kMinTurbulenceHeight, kMaxTurbulenceHeight);
  p.start_roll = o.params.max_roll;
  p.start_pitch = o.params.max_pitch;
  const HoverFlightResult r = flyHover(model, controller, p);
  const double disk = strokeDiskArea(*model, controller.amplitude);
  const double ideal = idealHoverPower(r.mass * 9.81, p.world.air.density, disk);
  ok = r.min_height >= altitude - 0.3 && r.max_height <= altitude + 0.3 && r.min_upright >= 0.9 &&
       r.max_stroke_oscillation < 0.05 && r.specificPower() <= 100.0;
  char line[1024];
  std::snprintf(
      line, sizeof line,
      "hover at %g m, wind %g m/s%s, %g s at %g ms (figures after %g s), gains %s:\n"
      "  height %.3f to %.3f m (rms %.4f m), lowest up-component %.4f, largest height range in a "
      "stroke %.1f mm, drift %.2f m, %.2f Hz\n"
      "  from t = 0: lowest %.3f m, largest tilt %.1f deg (%.1f deg at the start)\n"
      "  mechanical power of the motors: %.3f W positive (%.1f W/kg of its %.1f g), "
      "%.3f W net\n"
      "  figure of merit: ideal %.3f W (actuator disk of %.4f m^2) / %.3f W = %.2f\n%s\n",
      altitude, o.params.wind, turbulenceNote(o.params.turbulence).c_str(), p.duration,
      1000.0 * p.world.step_size, p.settle, o.gains.empty() ? "by hand" : o.gains.c_str(),
      r.min_height, r.max_height, r.altitude_rms, r.min_upright, 1000.0 * r.max_stroke_oscillation,
      r.drift.norm(), r.mean_frequency, r.lowest_height,
      std::acos(std::clamp(r.lowest_upright, -1.0, 1.0)) * 180.0 / M_PI,
      r.start_tilt * 180.0 / M_PI, r.positive_power, r.specificPower(), 1000.0 * r.mass,
      r.net_power, ideal, disk, r.positive_power, ideal / r.positive_power, ok ? "pass" : "FAIL");
  return line;
}

}  // namespace flapsim
