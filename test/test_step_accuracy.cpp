// Which step sizes a creature may be flown at (flapsim/step_accuracy.h), and evolution flying
// its episodes at them (evolve --step-sizes auto, the robust preset's default): the flap unit's
// open-loop climb at 4 ms is within 5 % of the one at 1/16 ms (with the products omitted at 8
// ms not; in the default air, the products shed, at 8 ms too); so is a chain's,
// whose link springs, too stiff for an explicit step there, act implicitly; the turn substep
// is chosen with the step. (Until the stiffness test counted the air a wing carries, a wing's
// drag was linearised at 4 ms, and neither was accurate there: 14.4 % and 11.8 %.)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"
#include "flapsim/make_creature.h"
#include "flapsim/step_accuracy.h"

namespace flapsim {
namespace {

const StrokeCommand kStroke{40.0, 10.0, 1.2};  // the robust preset's middle rate

// The air with the added mass's products omitted, where the first three tests were measured.
WorldParams omittedAir() {
  WorldParams p;
  p.air.added_mass_products = AddedMassProducts::kOmitted;
  return p;
}

// Measured against 1/16 ms (0.861 m in 3 s), with the products omitted: 8 ms climbs 10.2 %
// less, 4 ms 4.2 %, 2 ms 1.5 %, 1 ms 0.08 %.
TEST(StepAccuracy, WithTheProductsOmittedTheFlapUnitIsAccurateAtFourMsNotEight) {
  const CreatureModelPtr unit = parseCreatureModel(makeCreatureUrdf(1, "afc"), "afc");
  const std::vector<StepVerdict> v =
      stepVerdicts(unit, kStroke, omittedAir(), {0.008, 0.004, 0.002, 0.001});
  EXPECT_GT(v[0].relativeError(), 0.08);
  EXPECT_NE(v[0].why().find("height change"), std::string::npos) << v[0].why();
  EXPECT_LT(v[1].relativeError(), 0.05);
  EXPECT_TRUE(v[1].why().empty()) << v[1].why();
  EXPECT_LT(v[2].relativeError(), 0.02);
  EXPECT_LT(v[3].relativeError(), 0.002);
  EXPECT_GT(v[0].reference.height_change, 0.5);  // it climbs: a flight worth comparing
}

// afc_4's link springs (2 N m/rad) are too stiff for an explicit 4 ms step: they act
// implicitly there (they used to be capped, and chains flew at 1 and 0.5 ms). Measured against
// 1/16 ms (0.773 m in 3 s), with the products omitted: 8 ms 11.6 % less, 4 ms 1.3 %, 2 ms
// 0.28 %.
TEST(StepAccuracy, WithTheProductsOmittedChainsAreAccurateAtFourMsWithImplicitLinkSprings) {
  const CreatureModelPtr chain = parseCreatureModel(makeCreatureUrdf(4, "afc"), "afc4");
  ASSERT_FALSE(implicitJointValues(*chain, 0.004).empty());
  const std::vector<StepVerdict> v = stepVerdicts(chain, kStroke, omittedAir(), {0.008, 0.004});
  EXPECT_GT(v[0].relativeError(), 0.10);
  EXPECT_LT(v[1].relativeError(), 0.02);
  EXPECT_TRUE(v[1].why().empty()) << v[1].why();
}

// The turn substep is chosen with the step: of the accurate settings (h and h / 2 both within
// 5 % at one turn substep), the one taken in the fewest substeps. Measured (3 s open loop,
// against 1/16 ms): the unit at 4 ms with 4 ms pieces 4.35 % (2 ms 0.41 %), 2288 substeps over
// the two flights against 2324 with 2 ms pieces (2.59 %); afc_4 at 4 ms with 2 ms pieces
// 3.35 % (2 ms 2.92 %), 2360 substeps, its 4 ms pieces 20.0 % off. Both against 4537 at the
// 2 ms they flew at before. With the products omitted.
TEST(StepAccuracy, TheChoiceIsTheAccurateSettingTakenInTheFewestSubsteps) {
  for (int pairs : {1, 4}) {
    SCOPED_TRACE(pairs);
    const CreatureModelPtr model = parseCreatureModel(makeCreatureUrdf(pairs, "afc"), "afc");
    const std::vector<StepCandidate> all = stepCandidates(model, kStroke, omittedAir());
    ASSERT_EQ(all.size(), 9u);  // 4 ms: 4, 2, 1; 2 ms: 2, 1, 0.5; 1 ms: 1, 0.5; 0.5 ms: 0.5
    const StepCandidate* cheapest = nullptr;
    for (const StepCandidate& c : all) {
      if (c.accurate() && (!cheapest || c.substeps() < cheapest->substeps())) cheapest = &c;
    }
    ASSERT_NE(cheapest, nullptr);
    const double pieces = pairs == 1 ? 0.004 : 0.002;
    EXPECT_EQ(cheapest->step, 0.004);
    EXPECT_EQ(cheapest->turn_substep, pieces);
    EXPECT_LT(cheapest->at_step.relativeError(), 0.05);
    EXPECT_LT(cheapest->at_half.relativeError(), 0.03);
    // afc_4's 4 ms pieces are not accurate: the pieces matter for a chain.
    EXPECT_EQ(all[0].turn_substep, 0.004);
    EXPECT_EQ(all[0].accurate(), pairs == 1) << all[0].at_step.why();
    // Half the substeps of the 2 ms steps they were flown at (all[3]: 2 ms, 2 ms pieces).
    EXPECT_EQ(all[3].step, 0.002);
    EXPECT_LT(cheapest->substeps(), all[3].substeps() * 0.53);
    EXPECT_EQ(accurateStepChoice(model, kStroke, omittedAir()),
              (StepChoice{{0.004, 0.002}, pieces}));
    // A turn substep given is kept: only the step is chosen.
    EXPECT_EQ(accurateStepChoice(model, kStroke, omittedAir(), 0.0005),
              (StepChoice{{0.004, 0.002}, 0.0005}));
  }
}

// In the default air, the products shed into the wake, their impulse taken by the trapezoidal
// rule (MomentumBalance::addShedProducts), the climb converges faster. Measured against 1/16 ms
// (2.358 m in 3 s): the flap unit 8 ms 0.36 %, 4 ms 0.15 %, 2 ms 0.10 %, 1 ms 0.07 %; afc_4
// (3.048 m) 8 ms 1.23 %, 4 ms 0.35 %. Its choice: the unit at 4 ms with 2 ms pieces (0.55 %,
// 2 ms 0.31 %; its 4 ms pieces 5.8 % off), afc_4 at 4 ms with 4 ms pieces (1.27 %, 2 ms
// 1.73 %). Taken at each step's start alone, the shed impulse had the unit 17.1 % off at 4 ms,
// 7.5 % at 2 ms and 2.2 % at 1 ms, and evolution flew it at 2 and 1 ms.
TEST(StepAccuracy, InTheDefaultAirTheFlapUnitIsAccurateAtEightMsAndChainsAtFour) {
  const CreatureModelPtr unit = parseCreatureModel(makeCreatureUrdf(1, "afc"), "afc");
  const std::vector<StepVerdict> v = stepVerdicts(unit, kStroke, WorldParams(), {0.008, 0.004});
  EXPECT_LT(v[0].relativeError(), 0.005);
  EXPECT_LT(v[1].relativeError(), 0.002);
  EXPECT_GT(v[0].reference.height_change, 2.0);
  const CreatureModelPtr chain = parseCreatureModel(makeCreatureUrdf(4, "afc"), "afc4");
  const std::vector<StepVerdict> c = stepVerdicts(chain, kStroke, WorldParams(), {0.004});
  EXPECT_LT(c[0].relativeError(), 0.005);
  EXPECT_EQ(accurateStepChoice(unit, kStroke, WorldParams()), (StepChoice{{0.004, 0.002}, 0.002}));
  EXPECT_EQ(accurateStepChoice(chain, kStroke, WorldParams()), (StepChoice{{0.004, 0.002}, 0.004}));
}

// The robust preset finds them as its flags are read and hands the numbers on in its spec (the
// farm's workers and a resume fly the same steps without looking again); given step sizes
// stay as given.
TEST(StepAccuracy, EvolutionFliesTheAccurateStepSizes) {
  const EvolveOptions unit = parseEvolveArgs({});
  EXPECT_EQ(unit.params.episode.step_sizes, (std::vector<double>{0.004, 0.002}));
  EXPECT_FALSE(unit.params.auto_step_sizes);
  EXPECT_EQ(unit.params.episode.world.turn_substep, 0.002);
  EXPECT_EQ(unit.spec_args, (std::vector<std::string>{"--preset", "robust", "--step-sizes",
                                                      "0.004,0.002", "--turn-substep", "0.002"}));
  const EvolveOptions chain = parseEvolveArgs({"--pairs", "4", "--step-sizes", "auto"});
  EXPECT_EQ(chain.params.episode.step_sizes, (std::vector<double>{0.004, 0.002}));
  EXPECT_EQ(chain.spec_args,
            (std::vector<std::string>{"--preset", "robust", "--pairs", "4", "--step-sizes",
                                      "0.004,0.002", "--turn-substep", "0.004"}));
  const EvolveOptions again = parseEvolveArgs(chain.spec_args);
  EXPECT_EQ(again.params.episode.step_sizes, chain.params.episode.step_sizes);
  EXPECT_EQ(again.params.episode.world.turn_substep, 0.004);
  EXPECT_EQ(evaluationSpec(again.params).episode.world.turn_substep, 0.004);
  // A turn substep given stays, and the spec says it once.
  const EvolveOptions given = parseEvolveArgs({"--turn-substep", "0.001"});
  EXPECT_EQ(given.params.episode.world.turn_substep, 0.001);
  EXPECT_EQ(given.spec_args, (std::vector<std::string>{"--preset", "robust", "--turn-substep",
                                                       "0.001", "--step-sizes", "0.004,0.002"}));
  // Found in steady air: turbulence in the episodes does not move them.
  EXPECT_EQ(parseEvolveArgs({"--turbulence", "light"}).params.episode.step_sizes,
            (std::vector<double>{0.004, 0.002}));
  const EvolveOptions fixed = parseEvolveArgs({"--step-sizes", "0.001"});
  EXPECT_EQ(fixed.params.episode.step_sizes, std::vector<double>{0.001});
  EXPECT_EQ(fixed.params.episode.world.turn_substep, WorldParams().turn_substep);
  EXPECT_EQ(parseEvolveArgs({"--preset", "paper"}).params.episode.step_sizes,
            std::vector<double>{});
}

}  // namespace
}  // namespace flapsim
