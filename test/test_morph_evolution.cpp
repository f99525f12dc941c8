// Co-evolution of the hover creature's body and controller (evolve --preset morph,
// flapsim/morph_evolution.h): the genome's two parts, the body file, refused bodies scored as
// the worst episode while the run goes on, and the same bits whatever evaluates the tasks.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"
#include "flapsim/evolve_tool.h"
#include "flapsim/hover_gains.h"
#include "flapsim/morph_evolution.h"
#include "flapsim/morph_front.h"
#include "flapsim/text_file.h"
#include "morph_fixtures.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::evolveRefusal;
using test::flyingBody;
using test::flyingGenome;
using test::kLightMotors;
using test::lightMotors;
using test::shortSpec;
using test::writeFlyingBodyFile;

TEST(MorphEvolution, TheGenomeIsTheControllersGenesThenTheBodysEachCheckedByName) {
  const std::vector<double> genes = flyingGenome();
  ASSERT_EQ(genes.size(), static_cast<size_t>(kMorphGeneCount));
  EXPECT_EQ(checkMorphGenes(genes), "");
  std::vector<double> bad = genes;
  bad[2] = 1.25;
  EXPECT_EQ(checkMorphGenes(bad), "gene 2 (feather) is not a number in [-1, 1]");
  bad = genes;
  bad[kHoverGeneCount + 1] = -3.0;
  EXPECT_EQ(checkMorphGenes(bad), "body gene 1 (wing_chord) is -3, not a number in [-1, 1]");
  bad.pop_back();
  EXPECT_EQ(checkMorphGenes(bad),
            "24 genes, a morph genome has 25 (16 of the controller, 9 of the body)");
  // The individual: the body's genes build it, the controller's stroke stays 0.05 rad inside
  // its stroke limit.
  const MorphIndividual m = morphFromGenes(genes, 3.0, lightMotors());
  EXPECT_EQ(m.body.refusal, "");
  EXPECT_DOUBLE_EQ(m.body.params.max_power, 4.5);
  EXPECT_NEAR(m.body.params.stall_torque, HoverParams().stall_torque, 1e-15);
  EXPECT_DOUBLE_EQ(m.controller.max_stroke, m.body.params.stroke_limit - 0.05);
  EXPECT_NEAR(m.controller.trim_frequency, 13.321546513237099, 1e-12);  // the gains file's
  EXPECT_EQ(m.controller.altitude, 3.0);
}

// A body the budget refuses scores the worst an episode can, exactly; one that flies scores
// above it; the same bits on any thread count and through the runner.
TEST(MorphEvolution, ARefusedBodyScoresTheWorstEpisodeAndTheRunGoesOnWithTheOthers) {
  const EvaluationSpec spec = shortSpec();
  ASSERT_EQ(spec.kind, EvolveKind::kMorph);
  const EpisodeRunner runner(spec);
  ASSERT_EQ(runner.weightCount(), kMorphGeneCount);
  const std::vector<double> flying = flyingGenome();
  std::vector<double> refused = flying;
  refused[kHoverGeneCount + 6] = -1.0;  // an 8 g body for 6 g of payload and 9 g of motors
  ASSERT_NE(
      morphFromGenes(refused, 3.0, lightMotors()).body.refusal.find("mass budget does not close"),
      std::string::npos);
  std::vector<EpisodeTask> tasks;
  for (const auto& g : {flying, refused}) {
    for (int k = 0; k < 2; ++k) tasks.push_back(EpisodeTask{g, k});
  }
  const std::vector<double> one = InProcessEvaluator(spec, 1).evaluate(tasks);
  const std::vector<double> two = InProcessEvaluator(spec, 2).evaluate(tasks);
  EXPECT_EQ(one, two);
  EXPECT_EQ(runner.evaluate(tasks[0]), one[0]);
  EXPECT_EQ(one[2], -fitnessBound(spec));
  EXPECT_EQ(one[3], -fitnessBound(spec));
  // hover_1 holds its setpoint (the first episode level in still air, the second tilted in
  // wind): -0.24 and -0.28, most of it the power term (0.5 x 46 W/kg / 100), where a refused
  // body scores -fitnessBound (-359.5 - 78.5, the 4 s free fall).
  EXPECT_GT(one[0], -0.3);
  EXPECT_GT(one[1], -0.3);
  // A gene out of its range is a task that does not fit, refused by name.
  std::vector<double> out_of_range = flying;
  out_of_range[kHoverGeneCount] = 2.0;
  EXPECT_NE(runner.check(EpisodeTask{out_of_range, 0}).find("body gene 0 (wing_span)"),
            std::string::npos);
}

// The fall term: nothing within the hover fitness's 10 m of sag, then 1 per m up to a free
// fall over the episode (g T^2 / 2 = 78.48 m in 4 s), and a flip counts as that whole fall.
TEST(MorphEvolution, TheFallTermCountsTheSinkBeyondTenMetresUpToAFreeFallAndAFlipAsAFreeFall) {
  EpisodeParams e = morphPreset().episode;
  e.duration = 4.0;
  HoverFlightResult r;
  r.start_sag = 5.0;
  EXPECT_EQ(morphFallTerm(r, e), 0.0);
  r.start_sag = 30.0;
  EXPECT_NEAR(morphFallTerm(r, e), 20.0, 1e-12);
  r.start_sag = 500.0;
  EXPECT_NEAR(morphFallTerm(r, e), 78.48, 1e-12);
  r.start_sag = 1.0;
  r.flipped = true;
  EXPECT_NEAR(morphFallTerm(r, e), 78.48, 1e-12);
  EXPECT_NEAR(morphFitnessBound(e), hoverFitnessBound(e) + 78.48, 1e-12);
}

// The front's objectives: hover_1 flies its two episodes at about its 45 W/kg with a loss of
// centimetres, the same bits on 1 and 2 threads; a refused body has no objectives and rank -1,
// and the CSV names its refusal.
TEST(MorphFront, HoverOneScoresItsPowerAndARefusedBodyIsLeftOffTheFront) {
  const EvaluationSpec spec = shortSpec();
  std::vector<double> refused = flyingGenome();
  refused[kHoverGeneCount + 6] = -1.0;
  const std::vector<std::vector<double>> genomes = {flyingGenome(), refused};
  const std::vector<MorphScore> one = morphScores(genomes, spec, 1);
  const std::vector<MorphScore> two = morphScores(genomes, spec, 2);
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[0].power_per_kg, two[0].power_per_kg);
  EXPECT_EQ(one[0].loss, two[0].loss);
  EXPECT_EQ(one[0].refusal, "");
  EXPECT_NEAR(one[0].power_per_kg, 45.5, 3.0);
  EXPECT_LT(one[0].loss, 0.1);
  EXPECT_NEAR(one[0].mass, 0.018, 1e-9);
  EXPECT_NE(one[1].refusal.find("mass budget does not close"), std::string::npos);
  EXPECT_EQ(morphRanks(one), (std::vector<int>{0, -1}));
  const std::string csv = morphFrontCsv(genomes, one, morphRanks(one), lightMotors());
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "member,rank,power_w_per_kg,loss_m,mass_g,wing_span,wing_chord,stroke_limit,"
            "max_power,no_load_speed,hinge_stiffness,body_mass,com_drop,hinge_below_top,"
            "motors_g,ballast_g,refusal");
  EXPECT_NE(csv.find(",0.12,0.045,1.5,4.5,300,0.035,0.016,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("1,-1,"), std::string::npos) << csv;
}

// The fitness is the two objectives weighed: at --power-weight 5 a genome's mean episode
// fitness is -(its loss + 5 x its W/kg / 100), the front's two numbers.
TEST(MorphFront, TheFitnessIsMinusTheLossLessThePowerAtItsWeight) {
  std::vector<std::string> args = {"--preset", "morph", "--episodes", "2", "--duration",     "4",
                                   "--settle", "2",     "--seed",     "4", "--power-weight", "5"};
  args.insert(args.end(), kLightMotors.begin(), kLightMotors.end());
  const EvaluationSpec spec = evaluationSpecFromArgs(args);
  ASSERT_EQ(spec.morph.power_weight, 5.0);
  const EpisodeRunner runner(spec);
  const double fitness =
      0.5 * (runner.evaluate({flyingGenome(), 0}) + runner.evaluate({flyingGenome(), 1}));
  const MorphScore s = morphScores({flyingGenome()}, spec, 1).front();
  EXPECT_NEAR(fitness, -(s.loss + 5.0 * s.power_per_kg / 100.0), 1e-12);
  EXPECT_LT(fitness, -2.0);  // the power term, 5 x 45 W/kg / 100, dominates
}

// The body file reads back as the genes it was written from; bad files are refused by key.
TEST(MorphEvolution, ABodyFileReadsBackItsGenesAndBadOnesAreRefusedByKey) {
  const std::vector<double> genes = flyingBody();
  const HoverParams body = bodyFromGenes(genes, MassBudget());
  const std::string text = bodyToYaml(body, MassBudget(), "a header");
  const std::vector<double> back = bodyGenesFromYaml(text, "body.yaml");
  ASSERT_EQ(back.size(), genes.size());
  for (size_t i = 0; i < genes.size(); ++i) EXPECT_NEAR(back[i], genes[i], 1e-15) << i;
  EXPECT_NE(text.find("# masses: "), std::string::npos);
  auto refusal = [](const std::string& yaml) {
    try {
      bodyGenesFromYaml(yaml, "b.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  std::string missing = text.substr(0, text.find("com_drop")) + "hinge_below_top: 0.02\n";
  EXPECT_EQ(refusal(missing), "b.yaml: 'com_drop' is missing");
  std::string wide = text;
  wide.replace(wide.find("wing_span: "), 15, "wing_span: 0.5 ");
  EXPECT_EQ(refusal(wide), "b.yaml: 'wing_span' is 0.5, not in [0.06, 0.24] m");
  EXPECT_EQ(refusal(text + "wing_mass: 0.001\n"), "b.yaml: unknown key 'wing_mass'");
}

// A tiny morph evolution: in process on 2 threads and through an evaluator answering in
// reverse order (as a farm may), the same history and best genome, bit for bit; seeded from
// a gains file and a body file, generation 0's first individual is those genes.
TEST(MorphEvolution, ATinyRunIsTheSameBitsInProcessAndThroughAnotherEvaluatorAndSeedsFromFiles) {
  const std::string dir = ::testing::TempDir() + "/morph_seed";
  const std::string body_file = writeFlyingBodyFile(dir);
  const std::vector<double> seed = flyingGenome();
  writeTextFile(dir + "/gains.yaml", hoverGainsToYaml(hoverParamsFromGenes(std::vector<double>(
                                         seed.begin(), seed.begin() + kHoverGeneCount))));
  std::optional<EvolveCheckpoint> none;
  std::vector<std::string> args = {"--preset",      "morph",  "--population", "4",
                                   "--generations", "1",      "--episodes",   "2",
                                   "--duration",    "2",      "--settle",     "1",
                                   "--seed",        "3",      "--init",       dir + "/gains.yaml",
                                   "--init-body",   body_file};
  args.insert(args.end(), kLightMotors.begin(), kLightMotors.end());
  EvolveOptions o = resolveEvolveOptions(args, 2, none);
  ASSERT_EQ(o.params.ga.initial_genes.size(), seed.size());
  for (size_t i = 0; i < seed.size(); ++i)
    EXPECT_NEAR(o.params.ga.initial_genes[i], seed[i], 1e-15);
  const EvolveResult in_process = evolveFlapController(o.params);
  test::ReverseEvaluator reverse(evaluationSpec(o.params));
  EvolveHooks hooks;
  hooks.evaluator = &reverse;
  const EvolveResult other = evolveFlapController(o.params, hooks);
  ASSERT_EQ(in_process.history.size(), other.history.size());
  for (size_t g = 0; g < other.history.size(); ++g) {
    EXPECT_EQ(in_process.history[g].best, other.history[g].best) << g;
    EXPECT_EQ(in_process.history[g].mean, other.history[g].mean) << g;
  }
  EXPECT_EQ(in_process.best_weights, other.best_weights);
  EXPECT_GT(in_process.history[0].best, -fitnessBound(evaluationSpec(o.params)));
}

// The seeds are part of the run's definition: the checkpoint keeps --init and --init-body, so
// that the Reproduce line of a resumed run still names them, once.
TEST(MorphEvolution, AResumedRunsCommandStillNamesItsSeeds) {
  const std::string dir = ::testing::TempDir() + "/morph_resume";
  const std::string body_file = writeFlyingBodyFile(dir);
  std::optional<EvolveCheckpoint> none;
  const EvolveOptions first = resolveEvolveOptions(
      {"--preset", "morph", "--generations", "0", "--population", "2", "--episodes", "1",
       "--duration", "1", "--settle", "0.5", "--init-body", body_file, "--out", dir},
      1, none);
  const std::string seeded = "--init-body " + body_file;
  EXPECT_EQ(evolveCommand(first),
            "evolve --preset morph --generations 0 --population 2 --episodes 1 --duration 1 "
            "--settle 0.5 " +
                seeded);
  EvolveHooks hooks;
  hooks.on_checkpoint = [&](EvolveCheckpoint c) {
    c.args = first.spec_args;
    writeCheckpointFile(dir + "/checkpoint.txt", c);
  };
  evolveFlapController(first.params, hooks);
  std::optional<EvolveCheckpoint> resume;
  const EvolveOptions resumed =
      resolveEvolveOptions({"--resume", dir, "--generations", "1"}, 1, resume);
  ASSERT_TRUE(resume.has_value());
  const std::string command = evolveCommand(resumed);
  EXPECT_NE(command.find(seeded), std::string::npos) << command;
  EXPECT_EQ(command.find(seeded), command.rfind(seeded)) << command;
}

// The flags that mean nothing to a morph (the flap network's) are refused by name, and
// --init-body outside --preset morph.
TEST(MorphEvolution, FlapFlagsAndABodySeedOutsideMorphAreRefusedByName) {
  EXPECT_EQ(evolveRefusal({"--preset", "morph", "--hidden", "4"}),
            "--hidden: not a flag of --preset morph (the hover controller's gains and body)");
  EXPECT_EQ(evolveRefusal({"--preset", "hover", "--init-body", "b.yaml"}),
            "--init-body: for --preset morph only (the body's)");
  EXPECT_EQ(evolveRefusal({"--preset", "hover", "--motor-specific-power", "300"}),
            "--motor-specific-power: for --preset morph only (the body's)");
  EXPECT_EQ(evolveRefusal({"--preset", "robust", "--init-body", "b.yaml"}),
            "--init-body: has no effect but with --preset morph (the flap network has no body)");
}

}  // namespace
}  // namespace flapsim
