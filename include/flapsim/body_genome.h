// The body genome of the hover creature (issue 44): the make_creature --layout hover
// parameters an evolution may change, each within bounds, and the mass budget that turns a
// genome into a body that could be built: the wings' and spars' masses from their size, the
// stroke motors' mass from the power they are rated for, both inside the body's mass with a
// fixed payload. A genome becomes a URDF through makeHoverUrdf and parseCreatureModel (the
// checks every URDF passes), or is refused by name before it flies. ROS-free; no clock.
#pragma once

#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/make_creature.h"

namespace flapsim {

/// What turns a body genome's sizes and ratings into masses.
struct MassBudget {
  /// kg: what the body carries besides its two stroke motors (battery, electronics, frame).
  /// Fixed, the same for every genome; the body's mass beyond payload and motors is ballast.
  double payload = 0.010;
  /// kg/m^2: the membrane's mass per area (hover_1's: 0.6 g on 0.12 x 0.045 m).
  double wing_areal_density = 0.0006 / (0.12 * 0.045);
  /// kg/m: the spar's mass per length (hover_1's: 0.4 g on 0.12 m).
  double spar_linear_density = 0.0004 / 0.12;
  /// W/kg: the stroke motors' rated mechanical power per kg of motor. The default is a
  /// geared brushed DC micro motor's (Pololu's micro metal gearmotor, 75:1 HPCB 12 V,
  /// pololu.com/product/5215: no-load 450 rpm, stall 1.0 kg cm, so a peak of stall torque x
  /// no-load speed / 4 = 1.16 W, at the datasheet's approximately 10 g): 116 W/kg, gearbox
  /// included. Coreless and brushless motors without a gearbox reach several times more.
  double motor_specific_power = 116.0;
};

/// Empty if every field of `budget` is finite and positive, else a message naming the field.
std::string validateMassBudget(const MassBudget& budget);

/// A gene: field `name` of HoverParams, from `min` (gene -1) to `max` (gene +1) linearly.
struct BodyGene {
  const char* name;
  double HoverParams::*member;
  double min;
  double max;
  const char* unit;
};
/// The genes in genome order: wing_span, wing_chord, stroke_limit, max_power (per stroke
/// motor), no_load_speed (its gearing), hinge_stiffness, body_mass (payload, motors and
/// ballast), com_drop (where the ballast puts the body's centre of mass), hinge_below_top.
/// The rest of HoverParams keeps hover_1's values, but for the masses the budget derives
/// (wing_mass, spar_mass) and the stall torque: 4 max_power / no_load_speed, a DC motor whose
/// torque-speed line peaks at its rated power.
const std::vector<BodyGene>& bodyGenes();
constexpr int kBodyGeneCount = 9;
constexpr double kBodyGeneRange = 1.0;

/// Empty if `genes` is a body genome (kBodyGeneCount finite genes within +-kBodyGeneRange),
/// else a message naming the first culprit (its index, name and value).
std::string checkBodyGenes(const std::vector<double>& genes);

/// The hover creature of a genome under `budget` (checkBodyGenes first: InputError naming the
/// gene); the budget is not checked here (checkMassBudget).
HoverParams bodyFromGenes(const std::vector<double>& genes, const MassBudget& budget);
/// The genome of `params`' genes (the inverse of bodyFromGenes on them; a value outside its
/// gene's bounds gives a gene outside +-1, which checkBodyGenes refuses).
std::vector<double> bodyGenesFromParams(const HoverParams& params);

/// The masses of a body under a budget (kg).
struct BodyMass {
  double motors = 0.0;   // both stroke motors: 2 max_power / motor_specific_power
  double payload = 0.0;  // the budget's
  double ballast = 0.0;  // body_mass - payload - motors (negative: the budget does not close)
  double wings = 0.0;    // both membranes and spars
  double total = 0.0;    // body_mass + wings
};
BodyMass bodyMass(const HoverParams& params, const MassBudget& budget);

/// Empty if the payload and both motors fit inside the body's mass, else a message giving the
/// masses that do not fit.
std::string checkMassBudget(const HoverParams& params, const MassBudget& budget);

/// A genome built into a creature, or refused.
struct BodyBuild {
  HoverParams params;      // the genome's body (bodyFromGenes), once its genes check out
  std::string urdf;        // the URDF, if built
  CreatureModelPtr model;  // its parsed model, if built
  std::string refusal;     // empty if built; else why not, naming the culprit
};

/// Builds the genome named `name`: checkBodyGenes, validateMassBudget, checkMassBudget, then
/// makeHoverUrdf and parseCreatureModel (the checks of any URDF). Never throws for a bad
/// genome: the refusal says which check failed and names the culprit.
BodyBuild buildBody(const std::vector<double>& genes, const MassBudget& budget,
                    const std::string& name);

}  // namespace flapsim
