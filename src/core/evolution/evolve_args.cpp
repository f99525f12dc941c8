#include "flapsim/evolve_args.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "evolution/evolve_flag_rules.h"
#include "flapsim/air_model.h"
#include "flapsim/cli_args.h"
#include "flapsim/episode_evaluator.h"
#include "flapsim/flight_check.h"
#include "flapsim/hover_evolution.h"
#include "flapsim/morph_evolution.h"

namespace flapsim {

namespace {

const char* const kSpec = "spec";  // the tag of the flags that define the evolution

const char* const kNotes =
    "Defaults in parentheses are those of the preset given (robust unless --preset paper,\n"
    "hover or morph; hover evolves the hover controller's gains, morph those gains and the\n"
    "hover creature's body together, and both refuse the flags of the flap network and of\n"
    "the flap units' disturbances)\n"
    "and the flags before --help. A checkpoint is written to DIR/checkpoint.txt after every\n"
    "generation; --resume DIR continues it with its own flags, then the ones given.\n";

void specFlags(CliParser& t, EvolveOptions& o) {
  EvolveParams& p = o.params;
  EpisodeParams& e = p.episode;
  FlapControllerParams& c = p.controller;
  t.custom(
       "--preset", {"NAME"}, [](const std::vector<std::string>&) {},  // applied first
       [&o] { return o.preset; }, "robust, paper, hover or morph; the flags below change it")
      .integer("--pairs", "N", &p.pairs, {1, kMaxEvolvePairs}, "wing pairs of the creature")
      .tag(kSpec)
      .integer("--generations", "G", &p.ga.generations, {0, kMaxGenerations},
               "generations after the initial one")
      .tag(kSpec)
      .integer("--population", "P", &p.ga.population, {2, kMaxPopulation}, "individuals")
      .tag(kSpec)
      .seed("--seed", "S", &p.ga.seed, "GA and start-attitude seed")
      .tag(kSpec)
      .real("--duration", "D", &e.duration, {0, kMaxEpisodeDuration, true}, "episode length, s")
      .tag(kSpec)
      .integer("--episodes", "E", &e.episodes, {1, kMaxEpisodes},
               "episodes per evaluation, start roll alternating +/-")
      .tag(kSpec)
      .integer("--episode-sets", "K", &p.episode_sets, {1, kMaxEpisodes},
               "sets of E episodes drawn; generation g is evaluated on set g mod K, every "
               "individual anew (1: the one fixed set; not with --selection nsga2)")
      .tag(kSpec)
      .real("--min-rate", "R", &c.min_downstroke_rate, {0, kMaxStrokeRate},
            "lowest downstroke rate, rad/s")
      .tag(kSpec)
      .real("--max-rate", "R", &c.max_downstroke_rate, {0, kMaxStrokeRate},
            "highest downstroke rate, rad/s")
      .tag(kSpec)
      .real("--upstroke-rate", "R", &c.upstroke_rate, {0, kMaxStrokeRate}, "upstroke rate, rad/s")
      .tag(kSpec);
  outputFlags(t, c, kSpec);
  t.real("--amplitude", "A", &c.amplitude, {0, kMaxStrokeAmplitude, true}, "stroke amplitude, rad")
      .tag(kSpec)
      .real("--stroke-offset", "A", &c.stroke_offset, {-kMaxStrokeAmplitude, kMaxStrokeAmplitude},
            "the strokes' mean angle, rad (> 0: raised, a dihedral)")
      .tag(kSpec)
      .real("--control-period", "P", &c.control_period, {kMinControlPeriod, kMaxControlPeriod},
            "network update period, s")
      .tag(kSpec);
}

// "on" or "off" into `field`.
std::function<void(const std::vector<std::string>&)> onOff(const std::string& flag, bool* field) {
  return [flag, field](const std::vector<std::string>& v) {
    if (v[0] != "on" && v[0] != "off") throw InputError(flag + " takes on or off");
    *field = v[0] == "on";
  };
}

std::function<std::string()> showOnOff(const bool* field) {
  return [field] { return std::string(*field ? "on" : "off"); };
}

// The step sizes flown (an empty list flies at the world's step size: that one).
std::string stepSizesText(const EpisodeParams& e) {
  std::string s = formatCliNumber(e.world.step_size);
  for (size_t k = 0; k < e.step_sizes.size(); ++k) {
    s = (k ? s + "," : "") + formatCliNumber(e.step_sizes[k]);
  }
  return s;
}

// Sensor noise, gusts and the altitude hold of the episodes.
void disturbanceFlags(CliParser& t, EvolveOptions& o) {
  EpisodeParams& e = o.params.episode;
  t.custom(
       "--noise", {"N"},
       [&e](const std::vector<std::string>& v) {
         e.imu_noise.orientation = e.imu_noise.angular_velocity =
             parseCliReal("--noise", v[0], {0, 1e3});
       },
       [&e] { return formatCliNumber(e.imu_noise.orientation); },
       "IMU noise: orientation N rad, angular velocity N rad/s")
      .tag(kSpec)
      .real("--altitude-noise", "M", &e.altitude_noise, {0, 1e3}, "altimeter noise, m")
      .tag(kSpec)
      .real("--velocity-noise", "V", &e.velocity_noise, {0, 1e3},
            "ground-speed sensor noise, m/s per axis (read by the climb input)")
      .tag(kSpec)
      .real("--gyro-bias", "B", &e.gyro_bias, {0, 1e3},
            "a constant gyro bias per episode, up to B rad/s, any direction")
      .tag(kSpec)
      .custom(
          "--turbulence", {"LEVEL"},
          [&e](const std::vector<std::string>& v) {
            e.world.air.turbulence.wind_at_6m = turbulenceWindFromFlag("--turbulence", v[0]);
          },
          [&e] { return formatCliNumber(e.world.air.turbulence.wind_at_6m) + " m/s at 6 m"; },
          "Dryden turbulence (MIL-F-8785C): none, light, moderate, severe or the wind at 6 m "
          "(m/s); a realisation per episode")
      .tag(kSpec)
      .flag("--real-air", &e.real_air, true,
            "--preset hover, morph: real air, all at once, as flight_check --real-air: wind 1 m/s "
            "from a drawn heading, light turbulence, a roll torque (0.5 x weight x half-span) "
            "for 0.5 s and a push on a drawn wing (4 x the weight) for 0.2 s at drawn times, "
            "sized to each episode's body, IMU noise 0.05, a gyro bias up to 0.02 rad/s, "
            "altimeter noise 0.05 m; --wind and --turbulence with it give its wind and "
            "turbulence instead")
      .tag(kSpec)
      .real("--gust-torque", "T", &e.gust_torque, {-kMaxTorque, kMaxTorque},
            "a roll torque of T N m at a random time, random sign (0: none; with --real-air in "
            "--preset hover or morph: 0 takes real air's away)")
      .tag(kSpec)
      .real("--gust-torque-time", "S", &e.gust_torque_duration, {0, kMaxEpisodeDuration, true},
            "for S s")
      .tag(kSpec)
      .real("--gust-force", "F", &e.gust_force, {-kMaxForce, kMaxForce},
            "a vertical push of F N on one wing at a random time (0: none; with --real-air in "
            "--preset hover or morph: 0 takes real air's away)")
      .tag(kSpec)
      .real("--gust-force-time", "S", &e.gust_force_duration, {0, kMaxEpisodeDuration, true},
            "for S s")
      .tag(kSpec)
      .text("--gust-link", "LINK", &e.gust_link,
            "the link pushed (empty: a wing drawn per episode, up or down)")
      .tag(kSpec)
      .custom(
          "--altitude", {"LO", "HI"},
          [&e](const std::vector<std::string>& v) {
            e.min_altitude = parseCliReal("--altitude", v[0], {-kMaxPosition, kMaxPosition});
            e.max_altitude = parseCliReal("--altitude", v[1], {e.min_altitude, kMaxPosition});
            e.altitude_hold = true;
          },
          [&e] { return formatCliNumber(e.min_altitude) + " " + formatCliNumber(e.max_altitude); },
          "hold a setpoint drawn in [LO, HI] m; a sample scores -|height - setpoint| - (1 - "
          "up-component)")
      .tag(kSpec)
      .custom("--altitude-hold", {"B"}, onOff("--altitude-hold", &e.altitude_hold),
              showOnOff(&e.altitude_hold), "on/off; off: climb, a sample scores its height")
      .tag(kSpec);
}

void robustFlags(CliParser& t, EvolveOptions& o) {
  EvolveParams& p = o.params;
  EpisodeParams& e = p.episode;
  t.custom(
       "--roll", {"LO", "HI"},
       [&e](const std::vector<std::string>& v) {
         e.min_roll = parseCliReal("--roll", v[0], {0, M_PI});
         e.max_roll = parseCliReal("--roll", v[1], {e.min_roll, M_PI});
       },
       [&e] { return formatCliNumber(e.min_roll) + " " + formatCliNumber(e.max_roll); },
       "start roll range, rad")
      .tag(kSpec)
      .real("--pitch", "P", &e.max_pitch, {0, M_PI}, "start pitch range +-P, rad")
      .tag(kSpec)
      .custom(
          "--link-axis", {"A"}, linkAxisSetter(&p.unit.link_axis),
          [&p] { return toString(p.unit.link_axis); }, "axis of the joints between units")
      .tag(kSpec)
      .real("--link-stiffness", "K", &p.unit.link_stiffness, {0, 1e6},
            "spring on the joints between units, N m/rad")
      .tag(kSpec)
      .real("--start-rate", "W", &e.max_start_rate, {0, kMaxStartRate},
            "start angular velocity, up to W rad/s per axis")
      .tag(kSpec)
      .real("--gust", "G", &e.max_gust, {0, kMaxGust}, "a horizontal wind step of up to G m/s")
      .tag(kSpec)
      .custom(
          "--wind", {"LO", "HI"},
          [&e](const std::vector<std::string>& v) {
            e.min_wind = parseCliReal("--wind", v[0], {0, kMaxGust});
            e.max_wind = parseCliReal("--wind", v[1], {e.min_wind, kMaxGust});
          },
          [&e] { return formatCliNumber(e.min_wind) + " " + formatCliNumber(e.max_wind); },
          "steady wind from t = 0, speed uniform in [LO, HI] m/s, any heading")
      .tag(kSpec);
  disturbanceFlags(t, o);
  t.custom(
       "--step-sizes", {"LIST"},
       [&p, &e](const std::vector<std::string>& v) {
         p.auto_step_sizes = v[0] == "auto";
         if (!p.auto_step_sizes) {
           e.step_sizes = parseCliReals("--step-sizes", v[0], {1e-6, 0.1}, kMaxStepSizes);
         }
       },
       [&p, &e] { return p.auto_step_sizes ? std::string("auto") : stepSizesText(e); },
       "step sizes drawn per episode, s, e.g. 0.001,0.0005; auto: the creature's largest "
       "accurate step and its half (flapsim/step_accuracy.h)")
      .tag(kSpec);
  t.custom(
       "--turn-substep", {"S"},
       [&p, &e](const std::vector<std::string>& v) {
         e.world.turn_substep = turnSubstepFromFlag("--turn-substep", v[0]);
         p.turn_substep_given = true;
       },
       [&e] { return formatCliNumber(e.world.turn_substep); },
       "a step in which a wing turns is cut into pieces of at most S s (0: never); with "
       "--step-sizes auto chosen with the steps")
      .tag(kSpec)
      .real("--flip-penalty", "P", &e.flip_penalty, {0, kMaxFlipPenalty},
            "a flip ends the episode, less P m (0: off)")
      .tag(kSpec)
      .custom(
          "--crash-height", {"H"},
          [&e](const std::vector<std::string>& v) {
            e.crash_height =
                v[0] == "off" ? -std::numeric_limits<double>::infinity()
                              : parseCliReal("--crash-height", v[0], {-kMaxPosition, kMaxPosition});
          },
          [&e] {
            return std::isfinite(e.crash_height) ? formatCliNumber(e.crash_height)
                                                 : std::string("off");
          },
          "the root below H m (the scenarios' ground: 0) ends the episode as a flip does; off")
      .tag(kSpec);
  settleFlags(t, e, kSpec);
}

void controllerFlags(CliParser& t, EvolveOptions& o) {
  EvolveParams& p = o.params;
  FlapControllerParams& c = p.controller;
  t.custom(
       "--network", {"N"},
       [&c](const std::vector<std::string>& v) {
         try {
           c.network = flapNetworkFromString(v[0]);
         } catch (const std::invalid_argument& e) {
           throw InputError(std::string("--network: ") + e.what());
         }
       },
       [&c] { return toString(c.network); },
       "paper (2 outputs) or mirror (1 output; the left wing's is the mirrored inputs')")
      .tag(kSpec)
      .integer("--hidden", "H", &c.hidden, {1, kMaxHidden}, "hidden neurons")
      .tag(kSpec)
      .custom("--rate-inputs", {"B"}, onOff("--rate-inputs", &c.rate_inputs),
              showOnOff(&c.rate_inputs), "on/off: the gyro's roll, pitch, yaw rates as inputs")
      .tag(kSpec)
      .real("--rate-scale", "W", &c.rate_scale, {0, kMaxInputScale, true}, "rad/s per rate input")
      .tag(kSpec)
      .custom("--altitude-input", {"B"}, onOff("--altitude-input", &c.altitude_input),
              showOnOff(&c.altitude_input), "on/off: the altitude error as an input")
      .tag(kSpec)
      .real("--altitude-scale", "M", &c.altitude_scale, {0, kMaxInputScale, true}, "m per input")
      .tag(kSpec)
      .custom("--climb-input", {"B"}, onOff("--climb-input", &c.climb_input),
              showOnOff(&c.climb_input),
              "on/off: the root's vertical speed (the ground-speed sensor's) as an input")
      .tag(kSpec)
      .real("--climb-scale", "V", &c.climb_scale, {0, kMaxInputScale, true}, "m/s per input")
      .tag(kSpec)
      .custom("--chain-input", {"B"}, onOff("--chain-input", &c.chain_input),
              showOnOff(&c.chain_input),
              "on/off: each unit's place along the chain times the chain's pitch as an input, "
              "for --pairs > 1")
      .tag(kSpec)
      .real("--com-drop", "M", &p.unit.body_com_drop, {0, 10},
            "the unit's ballast, m below the hinges (the paper's unit: 0)")
      .tag(kSpec)
      .custom("--phase-lock", {"B"}, onOff("--phase-lock", &c.phase_lock), showOnOff(&c.phase_lock),
              "on/off: upstroke follows downstroke, fixed period")
      .tag(kSpec)
      .real("--pitch-gain", "K", &p.controller.pitch_gain, {0, kMaxPitchGain},
            "chain pitch term on top of the network, for --pairs > 1 (0: off)")
      .tag(kSpec)
      .custom(
          "--gene-range", {"G"},
          [&p](const std::vector<std::string>& v) {
            p.ga.gene_max = parseCliReal("--gene-range", v[0], {0, 1e6, true});
            p.ga.gene_min = -p.ga.gene_max;
          },
          [&p] { return formatCliNumber(p.ga.gene_max); },
          "initial range and bound of every weight, +-G")
      .tag(kSpec)
      .text("--air-model", "M", &p.episode.world.air.model, "air model of the episodes",
            airModelNames())
      .tag(kSpec);
  addedMassProductsFlag(t, &p.episode.world.air.added_mass_products).tag(kSpec);
}

void runFlags(CliParser& t, EvolveOptions& o) {
  t.integer("--threads", "T", &o.params.ga.threads, {1, 256},
            "parallel episodes; results do not depend on it")
      .text("--out", "DIR", &o.out_dir, "output directory")
      .text("--weights", "FILE", &o.weights_path,
            "weights YAML (empty: DIR/weights.yaml; --preset hover, morph: the gains, "
            "DIR/gains.yaml)")
      .flag("--no-plot", &o.plot, false, "do not run gnuplot")
      .text("--resume", "DIR", &o.resume_dir, "continue the run of DIR/checkpoint.txt")
      .text("--init", "FILE", &o.init_path,
            "seed generation 0 with this weights file (its network must be the evolution's; "
            "--preset hover, morph: a gains file)")
      .tag(kSpec)  // kept by the checkpoint, so that a resumed run's Reproduce line names it
      .text("--init-body", "FILE", &o.init_body_path,
            "--preset morph: seed generation 0 with this body file (evolve --preset morph's "
            "DIR/body.yaml)")
      .tag(kSpec)
      .flag("--farm", &o.farm, true, "evaluate on the flapsim_worker nodes under /flapsim_farm")
      .real("--farm-timeout", "S", &o.farm_timeout, {0, 1e6, true},
            "a call unanswered after S s is sent to another worker")
      .real("--farm-wait", "S", &o.farm_wait, {0, 1e7}, "give up after S s without any worker")
      .integer("--farm-inflight", "N", &o.farm_inflight, {1, 64}, "calls in flight per worker")
      .integer("--farm-batch", "N", &o.farm_batch, {1, kMaxTasksPerCall},
               "tasks per call (fewer if the worker's limit per call needs it)");
}

// The table over `o` (which must outlive it).
CliParser evolveTable(EvolveOptions& o) {
  CliParser t("usage: evolve [options]", kNotes);
  specFlags(t, o);
  robustFlags(t, o);
  morphFlags(t, o, kSpec);
  controllerFlags(t, o);
  runFlags(t, o);
  return t;
}

// The preset named in `args` (the last --preset), robust if none; its value is checked.
std::string presetOf(const std::vector<std::string>& args) {
  std::string preset = "robust";
  for (size_t i = 0; i + 1 < args.size(); ++i) {
    if (args[i] == "--preset") preset = args[i + 1];
  }
  if (preset != "robust" && preset != "paper" && preset != "hover" && preset != "morph") {
    throw InputError("--preset: " + quoteValue(preset) +
                     " is not one of robust, paper, hover, morph");
  }
  return preset;
}

// The presets as evolve flies them: the robust one at the creature's accurate step sizes.
EvolveParams presetParams(const std::string& preset) {
  if (preset == "paper") return paperPreset();
  if (preset == "hover") return hoverPreset();
  if (preset == "morph") return morphPreset();
  EvolveParams p = robustPreset();
  p.auto_step_sizes = true;
  return p;
}

// `flag`'s value in a spec's arguments: replaced if there, else appended.
void setSpecArg(std::vector<std::string>& spec, const std::string& flag, const std::string& value) {
  auto given = std::find(spec.begin(), spec.end(), flag);
  if (given == spec.end()) {
    spec.push_back(flag);
    spec.push_back(value);
  } else {
    *(given + 1) = value;
  }
}

}  // namespace

EvolveOptions parseEvolveArgs(const std::vector<std::string>& args, int threads, bool later_wins) {
  EvolveOptions o;
  o.preset = presetOf(args);
  o.params = presetParams(o.preset);
  o.params.ga.threads = threads;
  o.spec_args = {"--preset", o.preset};
  CliParser table = evolveTable(o);
  const std::vector<CliSeen> seen = table.parse(args, /*skip_remaps=*/true, later_wins);
  if (hoverPresetName(o.preset)) {
    checkHoverFlags(o.preset, seen, o.params);
  } else {
    checkDependentFlags(o.params, seen);
    // The chain pitch term's ceiling is at least the network's: --max-rate above its 75 rad/s
    // default raises it with it (else every such run would be refused for a flag not given).
    FlapControllerParams& c = o.params.controller;
    c.pitch_max_downstroke_rate = std::max(c.pitch_max_downstroke_rate, c.max_downstroke_rate);
  }
  if (o.params.episode.real_air) {
    // Real air's settings, but a --wind and a --turbulence given: they are its air then (as
    // flight_check --real-air takes them), the impulses, noises and gyro bias staying real air's.
    EpisodeParams& e = o.params.episode;
    const EpisodeParams given = e;
    setRealAirEpisodes(e);
    for (const CliSeen& s : seen) {
      const std::string& name = s.flag->names.front();
      if (name == "--gust-torque") e.real_air_torque = false;  // checkHoverFlags: 0, taken away
      if (name == "--gust-force") e.real_air_push = false;
      if (name == "--wind") {
        e.min_wind = given.min_wind;
        e.max_wind = given.max_wind;
      }
      if (name == "--turbulence") e.world.air.turbulence = given.world.air.turbulence;
    }
  }
  std::vector<const CliSeen*> spec;  // each flag once, with its last values
  for (const CliSeen& s : seen) {
    if (s.flag->tag != kSpec) continue;
    auto same = std::find_if(spec.begin(), spec.end(), [&](auto* x) { return x->flag == s.flag; });
    if (same == spec.end())
      spec.push_back(&s);
    else
      *same = &s;
  }
  for (const CliSeen* s : spec) {
    o.spec_args.push_back(s->flag->names.front());
    o.spec_args.insert(o.spec_args.end(), s->values.begin(), s->values.end());
  }
  if (!hoverPresetName(o.preset) && o.params.auto_step_sizes) {
    // Found once here; the spec (the farm's workers, a resume) carries the numbers.
    EvolveParams& p = o.params;
    const StepChoice choice = evolutionStepChoice(p);
    p.episode.step_sizes = choice.step_sizes;
    p.episode.world.turn_substep = choice.turn_substep;
    p.auto_step_sizes = false;
    setSpecArg(o.spec_args, "--step-sizes", stepSizesText(p.episode));
    if (!p.turn_substep_given) {
      setSpecArg(o.spec_args, "--turn-substep", formatCliNumber(choice.turn_substep));
    }
  }
  o.help = table.help();
  if (o.weights_path.empty()) {
    o.weights_path = o.out_dir + (hoverPresetName(o.preset) ? "/gains.yaml" : "/weights.yaml");
  }
  return o;
}

std::string evolveUsage(const std::vector<std::string>& args, int threads) {
  EvolveOptions o;
  try {
    o = parseEvolveArgs(args, threads);
  } catch (const InputError&) {
    o = parseEvolveArgs({}, threads);  // the defaults of a plain `evolve`
  }
  o.weights_path.clear();  // shown as "DIR/weights.yaml" by its help
  return evolveTable(o).usage();
}

void checkSpecArgs(const std::vector<std::string>& spec_args) {
  size_t bytes = 0;
  for (const std::string& a : spec_args) bytes += a.size();
  if (spec_args.size() > kMaxSpecArgs || bytes > kMaxSpecBytes) {
    throw InputError("spec: " + std::to_string(spec_args.size()) + " arguments of " +
                     std::to_string(bytes) + " bytes, over the limit of " +
                     std::to_string(kMaxSpecArgs) + " arguments or " +
                     std::to_string(kMaxSpecBytes) + " bytes");
  }
  EvolveOptions o;
  o.preset = presetOf(spec_args);
  o.params = presetParams(o.preset);
  CliParser table = evolveTable(o);
  // The flags first, before any value is read: values never start with "--".
  for (const std::string& a : spec_args) {
    for (const CliFlag& f : table.flags()) {
      if (f.tag == kSpec || f.names.front() == "--preset") continue;
      if (std::find(f.names.begin(), f.names.end(), a) != f.names.end() || a == "--help") {
        throw InputError("spec: '" + a + "' is not a flag of the evolution's definition");
      }
    }
  }
  const std::vector<CliSeen> seen = table.parse(spec_args);
  if (hoverPresetName(o.preset)) {
    checkHoverFlags(o.preset, seen, o.params);
  } else {
    checkDependentFlags(o.params, seen);
  }
}

EvaluationSpec evaluationSpecFromArgs(const std::vector<std::string>& spec_args) {
  checkSpecArgs(spec_args);
  try {
    return evaluationSpec(parseEvolveArgs(spec_args).params);
  } catch (const InputError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
}

}  // namespace flapsim
