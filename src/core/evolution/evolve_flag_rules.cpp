#include "evolution/evolve_flag_rules.h"

#include <algorithm>

#include "flapsim/output_mixer.h"

namespace flapsim {

namespace {

// The flags that mean nothing to the hover controller's evolution (the flap network's, the
// flap units' and their disturbances'): --preset hover and morph refuse them by name.
const std::vector<std::string> kNotHoverFlags = {
    "--pairs",          "--min-rate",         "--max-rate",       "--upstroke-rate",
    "--amplitude",      "--stroke-offset",    "--control-period", "--network",
    "--hidden",         "--rate-inputs",      "--altitude-input", "--chain-input",
    "--com-drop",       "--phase-lock",       "--pitch-gain",     "--gene-range",
    "--link-axis",      "--link-stiffness",   "--start-rate",     "--gust",
    "--gust-torque",    "--gust-torque-time", "--gust-force",     "--gust-force-time",
    "--gust-link",      "--altitude-noise",   "--altitude-hold",  "--gyro-bias",
    "--crash-height",   "--climb-input",      "--velocity-noise", "--upright-floor",
    "--rms-ceiling",    "--rate-scale",       "--altitude-scale", "--climb-scale",
    "--mixer-headroom", "--max-upstroke-rate"};

// The flags of --preset morph alone.
bool morphFlag(const std::string& name) {
  return name == "--init-body" || name == "--payload" || name == "--motor-specific-power" ||
         name == "--power-weight" || name == "--selection";
}

// Why a morph flag is the morph preset's alone.
std::string morphWhy(const std::string& name) {
  return name == "--selection" ? "its two objectives, W/kg and loss" : "the body's";
}

}  // namespace

void outputFlags(CliParser& t, FlapControllerParams& c, const char* spec_tag) {
  t.real("--max-upstroke-rate", "R", &c.max_upstroke_rate, {0, kMaxStrokeRate},
         "the network sets each upstroke, in [--upstroke-rate, R] rad/s (0: off; needs "
         "--network mirror and --phase-lock off)")
      .tag(spec_tag)
      .real("--mixer-headroom", "H", &c.mixer_headroom, {0, kMaxMixerHeadroom},
            "each output maps onto its rate range widened by H of its span at both ends, and "
            "the wings' rates are mixed back into it keeping their difference first (0: off)")
      .tag(spec_tag);
}

// The mass budget of --preset morph's bodies (flapsim/body_genome.h).
void morphFlags(CliParser& t, EvolveOptions& o, const char* spec_tag) {
  MassBudget& b = o.params.morph.budget;
  t.real("--payload", "KG", &b.payload, {0, 1e3, true},
         "--preset morph: the body's fixed payload beside its motors")
      .tag(spec_tag)
      .real("--motor-specific-power", "W_PER_KG", &b.motor_specific_power, {0, 1e6, true},
            "--preset morph: the stroke motors' rated power per kg (116: a geared micro motor)")
      .tag(spec_tag)
      .real("--power-weight", "M", &o.params.morph.power_weight, {0, 1e3},
            "--preset morph: the fitness's power term, m per 100 W/kg")
      .tag(spec_tag)
      .custom(
          "--selection", {"S"},
          [&o](const std::vector<std::string>& v) {
            if (v[0] != "elitist" && v[0] != "nsga2") {
              throw InputError("--selection: " + quoteValue(v[0]) +
                               " is not one of elitist, nsga2");
            }
            o.params.morph.nsga2 = v[0] == "nsga2";
          },
          [&o] { return std::string(o.params.morph.nsga2 ? "nsga2" : "elitist"); },
          "--preset morph: elitist (the GA on the fitness) or nsga2 (NSGA-II on two objectives, "
          "W/kg and loss; an even --population)")
      .tag(spec_tag);
  motorWorkFlag(t, &o.params.episode.world.motor_work,
                "--preset hover or morph, not with --added-mass-products omitted: how the "
                "fitness's W/kg takes the motors' work, transmitted or servo "
                "(WorldParams::motor_work)")
      .tag(spec_tag);
}

CliParser& motorWorkFlag(CliParser& t, MotorWorkMeter* meter, const char* help) {
  return t.custom(
      "--motor-work", {"M"},
      [meter](const std::vector<std::string>& v) {
        if (!motorWorkMeterFromName(v[0], meter)) {
          throw InputError("--motor-work: " + quoteValue(v[0]) +
                           " is not one of transmitted, servo");
        }
      },
      [meter] { return std::string(motorWorkMeterName(*meter)); }, help);
}

CliParser& addedMassProductsFlag(CliParser& t, AddedMassProducts* products) {
  return t.custom(
      "--added-mass-products", {"NAME"},
      [products](const std::vector<std::string>& v) {
        try {
          *products = parseAddedMassProducts(v[0]);
        } catch (const InputError& e) {
          throw InputError("--added-mass-products: " + std::string(e.what()));
        }
      },
      [products] { return std::string(addedMassProductsName(*products)); },
      "what the plates' added mass does beyond -A dnu (AirParams::added_mass_products): shed "
      "(the products shed into the wake, each plate -A dnu/dt; energy balances), kirchhoff "
      "(Kirchhoff's equations; energy balances, the flap unit turns over in pitch) or omitted "
      "(the air of the controllers evolved before December 2026; energy does not balance)");
}

bool hoverPresetName(const std::string& preset) { return preset == "hover" || preset == "morph"; }

void checkHoverFlags(const std::string& preset, const std::vector<CliSeen>& seen,
                     const EvolveParams& params) {
  const bool real_air = std::any_of(seen.begin(), seen.end(), [](const CliSeen& s) {
    return s.flag->names.front() == "--real-air";
  });
  for (const CliSeen& s : seen) {
    const std::string& name = s.flag->names.front();
    if (real_air && name == "--noise") {
      throw InputError(name + " is set by --real-air (give one or the other)");
    }
    if (real_air && (name == "--gust-torque" || name == "--gust-force")) {
      // 0: real air's impulse taken away (its size follows each body, so no other is given).
      if (parseCliReal(name, s.values[0], {-1e6, 1e6}) != 0.0) {
        throw InputError(name + " with --real-air in --preset " + preset +
                         " takes only 0 (the impulse taken away): its size follows each body");
      }
      continue;
    }
    if (std::find(kNotHoverFlags.begin(), kNotHoverFlags.end(), name) != kNotHoverFlags.end()) {
      throw InputError(name + ": not a flag of --preset " + preset +
                       (preset == "hover" ? " (the hover controller's gains)"
                                          : " (the hover controller's gains and body)"));
    }
    if (morphFlag(name) && preset != "morph") {
      throw InputError(name + ": for --preset morph only (" + morphWhy(name) + ")");
    }
    if (name == "--motor-work" && !params.episode.world.air.addedMassVelocityProducts()) {
      throw InputError(name + kMotorWorkWithoutProducts);
    }
  }
  const int n = params.ga.population;
  if (params.morph.nsga2 && (n < 4 || n % 2 != 0)) {
    throw InputError(
        "--selection nsga2: --population must be even and at least 4 (NSGA-II breeds its "
        "children in pairs), not " +
        std::to_string(n));
  }
}

// A flap network's evolution: the flags whose effect hangs on another's (a gust's duration
// or link without the gust, the altitude setpoints and the altimeter's noise without altitude
// hold or input, the settling time that only the hover preset's fitness counts after) are
// refused by name when that other leaves them without effect.
void checkDependentFlags(const EvolveParams& p, const std::vector<CliSeen>& seen) {
  const EpisodeParams& e = p.episode;
  for (const CliSeen& s : seen) {
    const std::string& name = s.flag->names.front();
    std::string why;
    if (name == "--gust-link" && e.gust_force == 0.0) why = "without --gust-force";
    if (name == "--gust-force-time" && e.gust_force == 0.0) why = "without --gust-force";
    if (name == "--gust-torque-time" && e.gust_torque == 0.0) why = "without --gust-torque";
    const bool settled_term = name == "--upright-floor" || name == "--rms-ceiling";
    const bool term_on =
        name == "--upright-floor" ? e.upright_floor > 0.0 : e.altitude_rms_ceiling > 0.0;
    if ((name == "--altitude" || settled_term) && !e.altitude_hold) {
      why = "without --altitude-hold on";
    } else if (settled_term && term_on && e.settle_time >= e.duration) {
      why = "with --settle at or after --duration (no sample settles)";
    }
    if (name == "--altitude-noise" && !p.controller.altitude_input) {
      why = "without an altitude input (--altitude-input on)";
    }
    if ((name == "--velocity-noise" || name == "--climb-scale") && !p.controller.climb_input) {
      why = "without a climb input (--climb-input on)";
    }
    if (name == "--altitude-scale" && !p.controller.altitude_input) {
      why = "without an altitude input (--altitude-input on)";
    }
    if (name == "--rate-scale" && !p.controller.rate_inputs) {
      why = "without the rate inputs (--rate-inputs on)";
    }
    if (name == "--settle" && e.upright_floor <= 0.0 && e.altitude_rms_ceiling <= 0.0) {
      why =
          "but with --preset hover or morph, --upright-floor or --rms-ceiling (the flap "
          "network's fitness has none without them)";
    }
    if (name == "--motor-work") {
      why = "but with --preset hover or morph (the flap network's fitness counts no power)";
    }
    if (morphFlag(name)) {
      why = name == "--selection" ? "but with --preset morph (a flap network has one fitness)"
                                  : "but with --preset morph (the flap network has no body)";
    }
    if (name == "--real-air") {
      throw InputError(
          "--real-air: for --preset hover or morph (a flap network's episodes take --wind, "
          "--turbulence, --gust-torque, --gust-force, --noise, --gyro-bias, --altitude-noise)");
    }
    if (name == "--max-upstroke-rate" && p.controller.max_upstroke_rate > 0.0 &&
        (p.controller.network != FlapNetwork::kMirror || p.controller.phase_lock)) {
      why = "without --network mirror and --phase-lock off (the net would set no upstroke)";
    }
    if (name == "--chain-input" && p.controller.chain_input && p.pairs < 2) {
      why = "on a single unit (--pairs 1: no chain)";
    }
    if ((name == "--link-axis" || name == "--link-stiffness") && p.pairs < 2) {
      why = "on a single unit (--pairs 1: no links between units)";
    }
    if (name == "--pitch-gain" && p.controller.pitch_gain > 0.0 && p.pairs < 2) {
      why = "on a single unit (--pairs 1: no chain)";
    }
    if (!why.empty()) throw InputError(name + ": has no effect " + why);
  }
}

namespace {

// A fitness term that counts after --settle: `name` LEVEL W, LEVEL in `level_range` into
// `level`, W (m per unit past the level) into `weight`; "0 0" is off.
CliParser& settledTermFlag(CliParser& t, const std::string& name, const std::string& metavar,
                           double* level, CliRange level_range, double* weight,
                           const std::string& help) {
  return t.custom(
      name, {metavar, "W"},
      [=](const std::vector<std::string>& v) {
        *level = parseCliReal(name, v[0], level_range);
        *weight = parseCliReal(name, v[1], {0, 1e6});
      },
      [=] { return formatCliNumber(*level) + " " + formatCliNumber(*weight); }, help);
}

}  // namespace

void settleFlags(CliParser& t, EpisodeParams& e, const char* spec_tag) {
  t.real("--settle", "S", &e.settle_time, {0, kMaxEpisodeDuration},
         "the altitude rms (--preset hover: every figure) counts after S s")
      .tag(spec_tag);
  settledTermFlag(t, "--upright-floor", "U", &e.upright_floor, {0, 1}, &e.upright_floor_weight,
                  "with --altitude-hold on: an episode whose lowest up-component after --settle "
                  "falls below U scores W m less per unit below it (flight_check's bar: 0.5; 0 0: "
                  "off)")
      .tag(spec_tag);
  settledTermFlag(t, "--rms-ceiling", "R", &e.altitude_rms_ceiling, {0, 1e3},
                  &e.altitude_rms_weight,
                  "with --altitude-hold on: an episode whose altitude rms after --settle exceeds R "
                  "m scores W m less per m over it (flight_check's bar: 0.3; 0 0: off)")
      .tag(spec_tag);
}

}  // namespace flapsim
