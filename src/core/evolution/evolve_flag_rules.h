// The rules by which evolve refuses a flag that would change nothing: the flap network's flags
// under the hover presets, and the flags whose effect hangs on another's. Private to
// flapsim_core (evolve_args.cpp).
#pragma once

#include <string>
#include <vector>

#include "flapsim/cli_args.h"
#include "flapsim/evolve.h"

namespace flapsim {

/// The presets that evolve the hover controller (and with morph its body).
bool hoverPresetName(const std::string& preset);

/// Throws InputError naming the first flag `seen` that means nothing to `preset` (hover or
/// morph): the flap network's, the flap units' and their disturbances', the body's outside
/// morph.
void checkHoverFlags(const std::string& preset, const std::vector<CliSeen>& seen);

/// A flap network's evolution: throws InputError naming the first flag `seen` whose effect
/// hangs on another's that `p` leaves without effect.
void checkDependentFlags(const EvolveParams& p, const std::vector<CliSeen>& seen);

}  // namespace flapsim
