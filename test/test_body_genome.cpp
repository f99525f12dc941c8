// The body genome of the hover creature and its mass budget (flapsim/body_genome.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "flapsim/body_genome.h"
#include "flapsim/hover_flight.h"
#include "flapsim/hover_gains.h"

namespace flapsim {
namespace {

std::vector<double> middleGenome() { return std::vector<double>(kBodyGeneCount, 0.0); }

// The middle of every gene but max_power's: 0.645 W per motor, 11.1 g of motors in a 29 g body
// (the middle's 3.025 W motors, 52 g, do not fit it with the 10 g payload).
std::vector<double> closingGenome() {
  std::vector<double> genes = middleGenome();
  genes[3] = -0.8;
  return genes;
}

// The genome's ends are its genes' bounds: gene -1 gives each field its min, +1 its max.
TEST(BodyGenome, GeneMinusOneAndPlusOneGiveEachFieldItsBounds) {
  const MassBudget budget;
  const HoverParams low = bodyFromGenes(std::vector<double>(kBodyGeneCount, -1.0), budget);
  const HoverParams high = bodyFromGenes(std::vector<double>(kBodyGeneCount, 1.0), budget);
  ASSERT_EQ(bodyGenes().size(), static_cast<size_t>(kBodyGeneCount));
  for (const BodyGene& g : bodyGenes()) {
    EXPECT_DOUBLE_EQ(low.*g.member, g.min) << g.name;
    EXPECT_DOUBLE_EQ(high.*g.member, g.max) << g.name;
  }
  // The genome's inverse maps back.
  const std::vector<double> back = bodyGenesFromParams(high);
  for (double gene : back) EXPECT_DOUBLE_EQ(gene, 1.0);
}

// The budget's densities are hover_1's: at hover_1's wing (0.12 x 0.045 m) they give its 0.6 g
// membrane and 0.4 g spar.
TEST(BodyGenome, TheBudgetsDensitiesGiveHoverOnesWingAndSparMassesAtItsSize) {
  const HoverParams hover_1;
  std::vector<double> genes = bodyGenesFromParams(hover_1);
  ASSERT_EQ(checkBodyGenes(genes), "");
  const HoverParams p = bodyFromGenes(genes, MassBudget());
  EXPECT_NEAR(p.wing_span, 0.12, 1e-15);
  EXPECT_NEAR(p.wing_mass, hover_1.wing_mass, 1e-15);
  EXPECT_NEAR(p.spar_mass, hover_1.spar_mass, 1e-15);
}

// The stall torque is derived so that the motor's line torque x speed, stall_torque (1 - v /
// no_load_speed) v, peaks at the rated max_power (at half the no-load speed).
TEST(BodyGenome, TheMotorsTorqueSpeedLinePeaksAtItsRatedPower) {
  std::vector<double> genes = middleGenome();
  genes[3] = 0.4;   // max_power
  genes[4] = -0.3;  // no_load_speed
  const HoverParams p = bodyFromGenes(genes, MassBudget());
  const double v = 0.5 * p.no_load_speed;
  EXPECT_NEAR(p.stall_torque * (1.0 - v / p.no_load_speed) * v, p.max_power, 1e-12);
  EXPECT_NEAR(p.max_power, 0.05 + 0.7 * (6.0 - 0.05), 1e-12);
}

// The motors weigh their rated power over the specific power: 2 x 1 W at 116 W/kg is 17.24 g;
// with a 10 g payload a 27.24 g body closes the budget exactly, 1 mg less does not.
TEST(BodyGenome, TheBudgetClosesWhenPayloadAndMotorsFitTheBodyMassAndNotOneMilligramLess) {
  const MassBudget budget;
  HoverParams p;
  p.max_power = 1.0;
  p.body_mass = budget.payload + 2.0 / 116.0;
  const BodyMass m = bodyMass(p, budget);
  EXPECT_NEAR(m.motors, 0.0172414, 1e-7);
  EXPECT_NEAR(m.ballast, 0.0, 1e-15);
  EXPECT_NEAR(m.total, p.body_mass + 2.0 * (p.wing_mass + p.spar_mass), 1e-15);
  p.body_mass += 1e-12;  // rounding on the right side
  EXPECT_EQ(checkMassBudget(p, budget), "");
  p.body_mass -= 1e-6;
  const std::string err = checkMassBudget(p, budget);
  EXPECT_NE(err.find("mass budget does not close"), std::string::npos) << err;
  EXPECT_NE(err.find("motors 17.2414 g"), std::string::npos) << err;
}

// hover_1 as designed (3 W stroke motors in a 16 g body) does not close the default budget:
// its motors alone would weigh 52 g.
TEST(BodyGenome, HoverOnesThreeWattMotorsDoNotFitItsSixteenGramBody) {
  const std::string err = checkMassBudget(HoverParams(), MassBudget());
  EXPECT_NE(err.find("motors 51.7241 g"), std::string::npos) << err;
  EXPECT_NE(err.find("body_mass 16 g"), std::string::npos) << err;
}

// A built genome is a creature whose mass is the body's plus both wings' and spars', and whose
// stroke motors are the genome's.
TEST(BodyGenome, ABuiltGenomeIsACreatureOfItsMassesAndMotors) {
  const std::vector<double> genes = closingGenome();
  const MassBudget budget;
  const BodyBuild b = buildBody(genes, budget, "morph_0");
  ASSERT_EQ(b.refusal, "");
  ASSERT_TRUE(b.model);
  const HoverParams p = bodyFromGenes(genes, budget);
  EXPECT_NEAR(b.model->totalMass(), bodyMass(p, budget).total, 1e-12);
  int motors = 0;
  for (const JointModel& j : b.model->joints) {
    if (!j.motor) continue;
    ++motors;
    EXPECT_NEAR(j.motor->stall_torque, p.stall_torque, 1e-9) << j.name;
    EXPECT_NEAR(j.motor->no_load_speed, p.no_load_speed, 1e-9) << j.name;
    EXPECT_NEAR(j.motor->max_power, p.max_power, 1e-9) << j.name;
  }
  EXPECT_EQ(motors, 2);
}

// Refusals name the culprit and build nothing: a gene beyond its bounds, a NaN, a short
// genome, a budget that does not close, a bad budget field, a mass make_creature refuses.
TEST(BodyGenome, EachRefusalNamesItsCulpritAndBuildsNothing) {
  const MassBudget budget;
  auto refusal = [&](std::vector<double> genes, const MassBudget& b) {
    const BodyBuild built = buildBody(genes, b, "morph_7");
    EXPECT_FALSE(built.model);
    EXPECT_TRUE(built.urdf.empty());
    EXPECT_EQ(built.refusal.rfind("body 'morph_7': ", 0), 0u) << built.refusal;
    return built.refusal;
  };
  std::vector<double> genes = middleGenome();
  genes[1] = 1.5;
  EXPECT_NE(refusal(genes, budget).find("gene 1 (wing_chord) is 1.5, not a number in [-1, 1]"),
            std::string::npos);
  genes[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal(genes, budget).find("gene 1 (wing_chord) is nan"), std::string::npos);
  EXPECT_NE(refusal(std::vector<double>(8, 0.0), budget).find("8 genes, a body genome has 9"),
            std::string::npos);
  genes = middleGenome();
  genes[3] = 1.0;   // 2 x 6 W: 103 g of motors
  genes[6] = -1.0;  // an 8 g body
  EXPECT_NE(refusal(genes, budget).find("mass budget does not close"), std::string::npos);
  MassBudget bad = budget;
  bad.motor_specific_power = -5.0;
  EXPECT_NE(refusal(closingGenome(), bad).find("motor_specific_power must be a positive number"),
            std::string::npos);
  bad = budget;
  bad.wing_areal_density = 1e12;  // a membrane beyond make_creature's 1e6 kg
  EXPECT_NE(refusal(closingGenome(), bad).find("make_creature refused it: hover creature"),
            std::string::npos);
}

// What the budget asks of a flier: hover_1's stroke draws a mean of under 0.5 W per motor, but
// its peaks do not fit motors rated 1 W: with them its evolved controller flips it (20 s
// holding 3 m), where its own 3 W motors hold it.
TEST(BodyGenome, HoverOnesStrokeDrawsUnderHalfAWattPerMotorButFlipsOnOneWattMotors) {
  HoverControllerParams controller =
      loadHoverGainsYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/hover_1_gains.yaml");
  controller.altitude = 3.0;
  HoverFlightParams flight;
  flight.duration = 20.0;
  flight.settle = 8.0;
  flight.end_on_flip = true;
  HoverParams body;
  const HoverFlightResult rated =
      flyHover(parseCreatureModel(makeHoverUrdf("h", body)), controller, flight);
  EXPECT_FALSE(rated.flipped);
  EXPECT_LT(rated.altitude_rms, 0.01);
  EXPECT_LT(rated.positive_power / 2.0, 0.5);
  body.max_power = 1.0;
  const HoverFlightResult small =
      flyHover(parseCreatureModel(makeHoverUrdf("h", body)), controller, flight);
  EXPECT_TRUE(small.flipped);
}

}  // namespace
}  // namespace flapsim
