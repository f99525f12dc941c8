#include "flapsim/evolve_args.h"

#include <sstream>
#include <stdexcept>

#include "flapsim/episode_evaluator.h"

namespace flapsim {

namespace {

const char* kUsage =
    "usage: evolve [options]\n"
    "  --preset NAME      robust (default) or paper; the options below change it\n"
    "                     (defaults shown are the paper preset's, the robust preset's after\n"
    "                     'robust')\n"
    "  --pairs N          wing pairs of the creature (1)\n"
    "  --generations G    generations after the initial one (200)\n"
    "  --population P     individuals (10)\n"
    "  --seed S           GA and start-attitude seed (1)\n"
    "  --threads T        parallel episodes (hardware threads); results do not depend on it\n"
    "  --duration D       episode length, s (30)\n"
    "  --episodes E       episodes per evaluation, start roll alternating +/- (8)\n"
    "  --min-rate R       lowest downstroke rate, rad/s (20)\n"
    "  --max-rate R       highest downstroke rate, rad/s (60)\n"
    "  --upstroke-rate R  upstroke rate, rad/s (10)\n"
    "  --amplitude A      stroke amplitude, rad (1.2)\n"
    "  --control-period P network update period, s (0.02)\n"
    "  --roll LO HI       start roll range, rad (0.035 0.087; robust 0 0.52)\n"
    "  --pitch P          start pitch range +-P, rad (0.035; robust 0.52)\n"
    "  --link-axis A      axis of the joints between units: roll or pitch (roll)\n"
    "  --link-stiffness K spring on the joints between units, N m/rad (2)\n"
    "  --start-rate W     start angular velocity, up to W rad/s per axis (0; robust 1)\n"
    "  --gust G           a horizontal wind step of up to G m/s (0)\n"
    "  --wind LO HI       steady wind from t = 0, speed uniform in [LO, HI] m/s, any heading\n"
    "                     (0 0; robust 0 2)\n"
    "  --noise N          IMU noise: orientation N rad, angular velocity N rad/s (0; robust 0.05)\n"
    "  --altitude-noise N altimeter noise, m (0; robust 0.05)\n"
    "  --gust-torque T    a roll torque of T N m at a random time, random sign (0; robust 0.05)\n"
    "  --gust-torque-time S  for S s (0.5)\n"
    "  --gust-force F     a vertical push of F N on one wing at a random time (0; robust 1)\n"
    "  --gust-force-time S   for S s (0.2)\n"
    "  --gust-link LINK   the link pushed (a wing drawn per episode, up or down)\n"
    "  --altitude LO HI   hold an altitude drawn in [LO, HI] m (robust 2 8); fitness\n"
    "                     -|height - setpoint| - (1 - up-component) per sample\n"
    "  --altitude-hold B  on/off (off; robust on); off: climb, fitness = height\n"
    "  --network N        paper (2 outputs) or mirror (1 output, left = mirrored inputs)\n"
    "                     (paper; robust mirror)\n"
    "  --hidden H         hidden neurons (2; robust 4)\n"
    "  --rate-inputs B    on/off: the gyro's roll, pitch, yaw rates as inputs (off; robust on)\n"
    "  --altitude-input B on/off: the altitude error as an input (off; robust on)\n"
    "  --com-drop M       the unit's ballast, m below the hinges (paper 0, robust 0.02)\n"
    "  --step-sizes LIST  step sizes drawn per episode, e.g. 0.001,0.0005 (robust)\n"
    "  --flip-penalty P   a flip ends the episode, less P m (0: off; robust 20)\n"
    "  --phase-lock B     on/off: upstroke follows downstroke, fixed period (robust on)\n"
    "  --pitch-gain K     chain pitch term on top of the network, for --pairs > 1 (0: off)\n"
    "  --gene-range G     initial range and bound of every weight, +-G (10)\n"
    "  --air-model M      air model of the episodes: pressure or quasi_steady (pressure)\n"
    "  --out DIR          output directory (evolve_out); a checkpoint is written there\n"
    "                     after every generation (DIR/checkpoint.txt)\n"
    "  --weights FILE     weights YAML (DIR/weights.yaml)\n"
    "  --no-plot          do not run gnuplot\n"
    "  --resume DIR       continue the run of DIR/checkpoint.txt (its flags; output to DIR)\n"
    "  --farm             evaluate on the flapsim_worker nodes under /flapsim_farm (ROS)\n"
    "  --farm-timeout S   a call unanswered after S s is sent to another worker (60)\n"
    "  --farm-wait S      give up after S s without any worker (120)\n"
    "  --farm-inflight N  calls in flight per worker (4)\n"
    "  --farm-batch N     tasks per call (1)\n";

int toInt(const std::string& flag, const std::string& v) {
  size_t used = 0;
  int x = 0;
  try {
    x = std::stoi(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != v.size()) throw InputError(flag + ": '" + v + "' is not an integer");
  return x;
}

double toDouble(const std::string& flag, const std::string& v) {
  size_t used = 0;
  double x = 0.0;
  try {
    x = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != v.size()) throw InputError(flag + ": '" + v + "' is not a number");
  return x;
}

bool onOff(const std::string& flag, const std::string& v) {
  if (v != "on" && v != "off") throw InputError(flag + " takes on or off, not '" + v + "'");
  return v == "on";
}

}  // namespace

std::string evolveUsage() { return kUsage; }

EvolveOptions parseEvolveArgs(const std::vector<std::string>& args, int threads) {
  EvolveOptions o;
  for (size_t i = 0; i + 1 < args.size(); ++i) {
    if (args[i] == "--preset") o.preset = args[i + 1];
  }
  if (o.preset == "paper") {
    o.params = paperPreset();
  } else if (o.preset == "robust") {
    o.params = robustPreset();
  } else {
    throw InputError("unknown preset '" + o.preset + "' (robust or paper)");
  }
  o.params.ga.threads = threads;
  o.spec_args = {"--preset", o.preset};
  EvolveParams& p = o.params;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.find(":=") != std::string::npos) continue;  // roslaunch's __name:=, __log:=
    if (a == "--help" || a == "-h") {
      o.help = true;
      continue;
    }
    if (a == "--no-plot") {
      o.plot = false;
      continue;
    }
    if (a == "--farm") {
      o.farm = true;
      continue;
    }
    if (i + 1 >= args.size()) throw InputError("missing value after " + a);
    const std::string v = args[++i];
    bool spec = true;  // the flag defines the evolution
    if (a == "--preset") {
      spec = false;  // applied first
    } else if (a == "--pairs") {
      p.pairs = toInt(a, v);
    } else if (a == "--generations") {
      p.ga.generations = toInt(a, v);
    } else if (a == "--population") {
      p.ga.population = toInt(a, v);
    } else if (a == "--seed") {
      try {
        p.ga.seed = std::stoull(v);
      } catch (const std::exception&) {
        throw InputError(a + ": '" + v + "' is not a seed");
      }
    } else if (a == "--duration") {
      p.episode.duration = toDouble(a, v);
    } else if (a == "--episodes") {
      p.episode.episodes = toInt(a, v);
    } else if (a == "--min-rate") {
      p.controller.min_downstroke_rate = toDouble(a, v);
    } else if (a == "--max-rate") {
      p.controller.max_downstroke_rate = toDouble(a, v);
    } else if (a == "--upstroke-rate") {
      p.controller.upstroke_rate = toDouble(a, v);
    } else if (a == "--amplitude") {
      p.controller.amplitude = toDouble(a, v);
    } else if (a == "--roll") {
      if (i + 1 >= args.size()) throw InputError("--roll takes two values");
      p.episode.min_roll = toDouble(a, v);
      p.episode.max_roll = toDouble(a, args[++i]);
      o.spec_args.insert(o.spec_args.end(), {a, v, args[i]});
      continue;
    } else if (a == "--link-axis") {
      try {
        p.unit.link_axis = linkAxisFromString(v);
      } catch (const std::invalid_argument& e) {
        throw InputError(std::string("--") + e.what());
      }
    } else if (a == "--link-stiffness") {
      p.unit.link_stiffness = toDouble(a, v);
    } else if (a == "--pitch") {
      p.episode.max_pitch = toDouble(a, v);
    } else if (a == "--start-rate") {
      p.episode.max_start_rate = toDouble(a, v);
    } else if (a == "--gust") {
      p.episode.max_gust = toDouble(a, v);
    } else if (a == "--noise") {
      p.episode.imu_noise.orientation = p.episode.imu_noise.angular_velocity = toDouble(a, v);
    } else if (a == "--altitude-noise") {
      p.episode.altitude_noise = toDouble(a, v);
    } else if (a == "--wind" || a == "--altitude") {
      if (i + 1 >= args.size()) throw InputError(a + " takes two values");
      const double lo = toDouble(a, v), hi = toDouble(a, args[++i]);
      if (a == "--wind") {
        p.episode.min_wind = lo;
        p.episode.max_wind = hi;
      } else {
        p.episode.altitude_hold = true;
        p.episode.min_altitude = lo;
        p.episode.max_altitude = hi;
      }
      o.spec_args.insert(o.spec_args.end(), {a, v, args[i]});
      continue;
    } else if (a == "--gust-torque") {
      p.episode.gust_torque = toDouble(a, v);
    } else if (a == "--gust-torque-time") {
      p.episode.gust_torque_duration = toDouble(a, v);
    } else if (a == "--gust-force") {
      p.episode.gust_force = toDouble(a, v);
    } else if (a == "--gust-force-time") {
      p.episode.gust_force_duration = toDouble(a, v);
    } else if (a == "--gust-link") {
      p.episode.gust_link = v;
    } else if (a == "--altitude-hold") {
      p.episode.altitude_hold = onOff(a, v);
    } else if (a == "--network") {
      try {
        p.controller.network = flapNetworkFromString(v);
      } catch (const std::invalid_argument& e) {
        throw InputError(a + ": " + e.what());
      }
    } else if (a == "--hidden") {
      p.controller.hidden = toInt(a, v);
    } else if (a == "--rate-inputs") {
      p.controller.rate_inputs = onOff(a, v);
    } else if (a == "--altitude-input") {
      p.controller.altitude_input = onOff(a, v);
    } else if (a == "--com-drop") {
      p.unit.body_com_drop = toDouble(a, v);
    } else if (a == "--flip-penalty") {
      p.episode.flip_penalty = toDouble(a, v);
    } else if (a == "--phase-lock") {
      p.controller.phase_lock = onOff(a, v);
    } else if (a == "--pitch-gain") {
      p.controller.pitch_gain = toDouble(a, v);
    } else if (a == "--step-sizes") {
      p.episode.step_sizes.clear();
      std::istringstream list(v);
      for (std::string item; std::getline(list, item, ',');) {
        p.episode.step_sizes.push_back(toDouble(a, item));
      }
    } else if (a == "--control-period") {
      p.controller.control_period = toDouble(a, v);
    } else if (a == "--gene-range") {
      p.ga.gene_max = toDouble(a, v);
      p.ga.gene_min = -p.ga.gene_max;
    } else if (a == "--air-model") {
      p.episode.world.air.model = v;
    } else {
      spec = false;
      if (a == "--threads") {
        p.ga.threads = toInt(a, v);
      } else if (a == "--out") {
        o.out_dir = v;
      } else if (a == "--weights") {
        o.weights_path = v;
      } else if (a == "--resume") {
        o.resume_dir = v;
      } else if (a == "--farm-timeout") {
        o.farm_timeout = toDouble(a, v);
      } else if (a == "--farm-wait") {
        o.farm_wait = toDouble(a, v);
      } else if (a == "--farm-inflight") {
        o.farm_inflight = toInt(a, v);
      } else if (a == "--farm-batch") {
        o.farm_batch = toInt(a, v);
      } else {
        throw InputError("unknown option " + a);
      }
    }
    if (spec) o.spec_args.insert(o.spec_args.end(), {a, v});
  }
  if (!(o.farm_timeout > 0.0)) throw InputError("--farm-timeout must be > 0");
  if (!(o.farm_wait >= 0.0)) throw InputError("--farm-wait must be >= 0");
  if (o.farm_inflight < 1) throw InputError("--farm-inflight must be >= 1");
  if (o.farm_batch < 1) throw InputError("--farm-batch must be >= 1");
  if (o.weights_path.empty()) o.weights_path = o.out_dir + "/weights.yaml";
  return o;
}

EvaluationSpec evaluationSpecFromArgs(const std::vector<std::string>& spec_args) {
  for (const auto& a : spec_args) {
    if (a == "--farm" || a == "--resume" || a == "--out" || a == "--weights" || a == "--threads") {
      throw InputError("spec: '" + a + "' is not a flag of the evolution's definition");
    }
  }
  try {
    return evaluationSpec(parseEvolveArgs(spec_args).params);
  } catch (const InputError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
}

}  // namespace flapsim
