// The rules by which evolve refuses a flag that would change nothing: the flap network's flags
// under the hover presets, and the flags whose effect hangs on another's; and the flags of the
// morph preset alone, and the settling time with the fitness terms that count after it. Private
// to flapsim_core (evolve_args.cpp).
#pragma once

#include <string>
#include <vector>

#include "flapsim/cli_args.h"
#include "flapsim/evolve.h"
#include "flapsim/evolve_args.h"

namespace flapsim {

/// The presets that evolve the hover controller (and with morph its body).
bool hoverPresetName(const std::string& preset);

/// Throws InputError naming the first flag `seen` that means nothing to `preset` (hover or
/// morph): the flap network's, the flap units' and their disturbances', the body's outside
/// morph; or an odd population (or under 4) for NSGA-II's selection in `params`.
void checkHoverFlags(const std::string& preset, const std::vector<CliSeen>& seen,
                     const EvolveParams& params);

/// The flags of --preset morph alone, tagged `spec_tag`: its bodies' mass budget
/// (flapsim/body_genome.h), the fitness's power weight and the selection.
void morphFlags(CliParser& t, EvolveOptions& o, const char* spec_tag);

/// Adds `--motor-work M` (transmitted or servo, anything else refused by name) writing `meter`,
/// with `help`; the added flag is the parser's last (to tag).
CliParser& motorWorkFlag(CliParser& t, MotorWorkMeter* meter, const char* help);

/// Adds `--added-mass-products NAME` (omitted, kirchhoff or shed, anything else refused by
/// name) writing `products`; the added flag is the parser's last (to tag).
CliParser& addedMassProductsFlag(CliParser& t, AddedMassProducts* products);

/// The flap network's output flags, tagged `spec_tag`: `--max-upstroke-rate R` (an upstroke
/// output) and `--mixer-headroom H` (the attitude-first mixer, flapsim/output_mixer.h).
void outputFlags(CliParser& t, FlapControllerParams& c, const char* spec_tag);

/// `--settle S` and the fitness terms that count after it, `--upright-floor U W` and
/// `--rms-ceiling R W` (a flap network holding an altitude), tagged `spec_tag`.
void settleFlags(CliParser& t, EpisodeParams& e, const char* spec_tag);

/// A flap network's evolution: throws InputError naming the first flag `seen` whose effect
/// hangs on another's that `p` leaves without effect.
void checkDependentFlags(const EvolveParams& p, const std::vector<CliSeen>& seen);

}  // namespace flapsim
