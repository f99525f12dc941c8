// The hover controller's evolution (evolve --preset hover): its genome maps to the gains and
// back, its episodes' fitness is a function of the genes alone (same bits on any thread count)
// and ranks broken controllers below the hand-designed one, its gains file reads back bit for
// bit, and bad input is refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"
#include "flapsim/evolve_tool.h"
#include "flapsim/flight_check.h"
#include "flapsim/hover_evolution.h"
#include "flapsim/hover_gains.h"
#include "flapsim/make_creature.h"
#include "flapsim/turbulence.h"

namespace flapsim {
namespace {

// Two short episodes of the hover preset.
EvaluationSpec shortSpec() {
  return evaluationSpecFromArgs(
      {"--preset", "hover", "--episodes", "2", "--duration", "6", "--settle", "3", "--seed", "4"});
}

std::vector<double> geneSet(const std::string& name, double value) {
  std::vector<double> genes(kHoverGeneCount, 0.0);
  for (size_t i = 0; i < hoverGenes().size(); ++i) {
    if (name == hoverGenes()[i].name) genes[i] = value;
  }
  return genes;
}

std::string message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(HoverEvolution, ZeroGenesAreTheHandDesignedGainsAndTheMapIsInvertible) {
  const HoverControllerParams hand;
  const HoverControllerParams zero = hoverParamsFromGenes(std::vector<double>(kHoverGeneCount));
  for (const HoverParamField& f : hoverParamFields()) EXPECT_EQ(zero.*f.member, hand.*f.member);
  // A gene of -1 on a gain is a zero gain, +1 twice the hand-designed one.
  EXPECT_EQ(hoverParamsFromGenes(geneSet("height_gain", -1.0)).height_gain, 0.0);
  EXPECT_EQ(hoverParamsFromGenes(geneSet("roll_gain", 1.0)).roll_gain, 2.0 * hand.roll_gain);
  EXPECT_EQ(hoverParamsFromGenes(geneSet("trim_frequency", -1.0)).trim_frequency,
            0.5 * hand.trim_frequency);
  // The start's genes: 0 to 0.8 s, and a share of 0.2 to 1.
  EXPECT_EQ(hoverParamsFromGenes(geneSet("start_time", -1.0)).start_time, 0.0);
  EXPECT_EQ(hoverParamsFromGenes(geneSet("start_time", 1.0)).start_time, 0.8);
  EXPECT_NEAR(hoverParamsFromGenes(geneSet("start_amplitude", -1.0)).start_amplitude, 0.2, 1e-15);
  EXPECT_NEAR(hoverParamsFromGenes(geneSet("start_amplitude", 1.0)).start_amplitude, 1.0, 1e-15);
  const std::vector<double> genes = {0.5,  -0.25, 0.125,  1.0, -1.0, 0.5,  0.75,  -0.5,
                                     0.25, 0.0,   -0.125, 0.5, 1.0,  -1.0, 0.375, -0.625};
  const std::vector<double> back = hoverGenesFromParams(hoverParamsFromGenes(genes));
  ASSERT_EQ(back.size(), genes.size());
  for (size_t i = 0; i < genes.size(); ++i) EXPECT_NEAR(back[i], genes[i], 1e-15) << i;
}

TEST(HoverEvolution, FitnessIsTheSameBitsOnAnyThreadCountAndRanksBrokenGenomesBelowTheHandOne) {
  const EvaluationSpec spec = shortSpec();
  ASSERT_EQ(spec.kind, EvolveKind::kHover);
  const EpisodeRunner runner(spec);
  ASSERT_EQ(runner.weightCount(), kHoverGeneCount);
  const std::vector<double> hand(kHoverGeneCount, 0.0);
  std::vector<double> no_hold = geneSet("height_gain", -1.0);
  no_hold[5] = -1.0;  // height_integral 0 too: nothing holds the setpoint
  const std::vector<double> slow = geneSet("trim_frequency", -1.0);  // 7.25 Hz
  std::vector<EpisodeTask> tasks;
  for (const auto& g : {hand, no_hold, slow}) {
    for (int k = 0; k < 2; ++k) tasks.push_back(EpisodeTask{g, k});
  }
  const std::vector<double> one = InProcessEvaluator(spec, 1).evaluate(tasks);
  const std::vector<double> two = InProcessEvaluator(spec, 2).evaluate(tasks);
  EXPECT_EQ(one, two);
  EXPECT_EQ(runner.evaluate(tasks[1]), one[1]);
  const double f_hand = one[0] + one[1], f_no_hold = one[2] + one[3], f_slow = one[4] + one[5];
  EXPECT_GT(f_hand, f_no_hold);
  EXPECT_GT(f_hand, f_slow);
  for (double f : one) EXPECT_LE(std::abs(f), fitnessBound(spec));
}

// The preset's first episode starts as hover.launch does (level, at rest, in still air, holding
// its start height); the others are drawn as without that rule, to the bit.
TEST(HoverEvolution, FirstEpisodeStartsLevelInStillAirAndTheOthersAreUnchanged) {
  EpisodeParams p = hoverPreset().episode;
  p.episodes = 4;
  p.seed = 9;
  ASSERT_TRUE(p.first_start_level);
  const std::vector<EpisodeStart> starts = episodeStarts(p);
  p.first_start_level = false;
  const std::vector<EpisodeStart> drawn = episodeStarts(p);
  EXPECT_EQ(starts[0].roll, 0.0);
  EXPECT_EQ(starts[0].pitch, 0.0);
  EXPECT_EQ(starts[0].wind, Vec3::Zero());
  EXPECT_EQ(starts[0].rate, Vec3::Zero());
  ASSERT_TRUE(starts[0].altitude.has_value());
  EXPECT_EQ(*starts[0].altitude, p.start_height);
  EXPECT_GT(drawn[0].wind.norm(), 0.0);  // what the rule replaced
  for (size_t k = 1; k < starts.size(); ++k) {
    EXPECT_EQ(starts[k].roll, drawn[k].roll);
    EXPECT_EQ(starts[k].wind, drawn[k].wind);
    EXPECT_EQ(starts[k].altitude, drawn[k].altitude);
  }
}

// The start's penalties: tilting more than 10 deg beyond the start tilt at any time costs
// kHoverStartTiltWeight per unit of up-component below cos(start tilt + 10 deg), and sinking
// more than kHoverMaxSag below the start height and the setpoint kHoverSagWeight per m.
TEST(HoverEvolution, TiltingTenDegreesBeyondTheStartAndSinkingArePenalised) {
  HoverFlightResult r;
  r.altitude_rms = 0.0;
  r.min_upright = 1.0;
  r.mass = 0.018;
  r.lowest_upright = std::cos(9.0 * M_PI / 180.0);
  EXPECT_EQ(hoverEpisodeFitness(r, 20.0), 0.0);
  r.lowest_upright = std::cos(12.0 * M_PI / 180.0);
  EXPECT_NEAR(hoverEpisodeFitness(r, 20.0),
              -kHoverStartTiltWeight * (std::cos(10.0 * M_PI / 180.0) - r.lowest_upright), 1e-15);
  r.start_tilt = 0.1;  // 5.7 deg at the start: 15.7 deg allowed
  EXPECT_EQ(hoverEpisodeFitness(r, 20.0), 0.0);
  // Sinking below the start height and the setpoint: free to kHoverMaxSag, then
  // kHoverSagWeight per m.
  r.start_sag = 0.04;
  EXPECT_EQ(hoverEpisodeFitness(r, 20.0), 0.0);
  r.start_sag = 0.15;
  EXPECT_NEAR(hoverEpisodeFitness(r, 20.0), -kHoverSagWeight * (0.15 - kHoverMaxSag), 1e-15);
}

TEST(HoverEvolution, BadGenomesKindsAndFlagsAreRefusedByName) {
  const EpisodeRunner runner(shortSpec());
  EXPECT_EQ(runner.check({std::vector<double>(13, 0.0), 0}), "13 weights, the controller has 16");
  EXPECT_EQ(runner.check({geneSet("roll_gain", NAN), 0}),
            "gene 6 (roll_gain) is not a number in [-1, 1]");
  EXPECT_EQ(runner.check({geneSet("feather", 1.5), 0}),
            "gene 2 (feather) is not a number in [-1, 1]");
  EXPECT_EQ(runner.check({std::vector<double>(16, 0.0), 2}), "episode 2 is not in [0, 2)");
  EXPECT_THROW(runner.evaluate({geneSet("amplitude", INFINITY), 0}), TaskError);
  EXPECT_EQ(message([] {
              parseEvolveArgs({"--preset", "helicopter"});
            }),
            "--preset: 'helicopter' is not one of robust, paper, hover, morph");
  EXPECT_EQ(message([] {
              parseEvolveArgs({"--preset", "hover", "--hidden", "4"});
            }),
            "--hidden: not a flag of --preset hover (the hover controller's gains)");
  EXPECT_EQ(message([] {
              evaluationSpecFromArgs({"--preset", "hover", "--pairs", "2"});
            }),
            "--pairs: not a flag of --preset hover (the hover controller's gains)");
  EXPECT_EQ(message([] {
              parseEvolveArgs({"--noise", "0.1", "--preset", "hover", "--real-air"});
            }),
            "--noise is set by --real-air (give one or the other)");
  EXPECT_EQ(message([] {
              parseEvolveArgs({"--preset", "morph", "--real-air", "--gust-torque", "0.01"});
            }),
            "--gust-torque with --real-air in --preset morph takes only 0 (the impulse taken "
            "away): its size follows each body");
  EXPECT_EQ(message([] {
              parseEvolveArgs({"--preset", "hover", "--gust-torque", "0"});
            }),
            "--gust-torque: not a flag of --preset hover (the hover controller's gains)");
  EXPECT_EQ(message([] { parseEvolveArgs({"--real-air"}); }),
            "--real-air: for --preset hover or morph (a flap network's episodes take --wind, "
            "--turbulence, --gust-torque, --gust-force, --noise, --gyro-bias, --altitude-noise)");
  EXPECT_EQ(message([] {
              evaluationSpecFromArgs({"--preset", "hover", "--settle", "12"});
            }),
            "evolve: the hover episodes' settling time must be shorter than their "
            "duration (--settle)");
}

// evolve --preset hover --real-air: the episodes fly flight_check --real-air's air (wind 1 m/s,
// light turbulence, IMU noise 0.05, gyro bias up to 0.02 rad/s, altimeter noise 0.05 m) and its
// two impulses sized to the body flown: a creature 4 x as heavy gets a push 4 x as strong. An
// episode is the flight with those gusts, and the impulses act (without them it flies
// otherwise).
TEST(HoverEvolution, RealAirEpisodesFlyFlightChecksRealAirSizedToTheBodyFlown) {
  const EvaluationSpec spec =
      evaluationSpecFromArgs({"--preset", "hover", "--real-air", "--episodes", "3", "--duration",
                              "6", "--settle", "3", "--seed", "4"});
  const EpisodeParams& e = spec.episode;
  EXPECT_TRUE(e.real_air);
  EXPECT_EQ(e.min_wind, 1.0);
  EXPECT_EQ(e.max_wind, 1.0);
  EXPECT_EQ(e.world.air.turbulence.wind_at_6m, turbulenceLevelWind("light"));
  EXPECT_EQ(e.imu_noise.orientation, 0.05);
  EXPECT_EQ(e.imu_noise.angular_velocity, 0.05);
  EXPECT_EQ(e.gyro_bias, 0.02);
  EXPECT_EQ(e.altitude_noise, 0.05);

  HoverParams light, heavy;
  heavy.body_mass =
      light.body_mass + 3.0 * parseCreatureModel(makeHoverUrdf("h", light))->totalMass();
  const CreatureModelPtr small = parseCreatureModel(makeHoverUrdf("light", light));
  const CreatureModelPtr big = parseCreatureModel(makeHoverUrdf("heavy", heavy));
  const FlightCheckParams check = realAirParams(FlightCheckParams(), *small);
  const EpisodeParams gusts = realAirGusts(e, *small);
  EXPECT_EQ(gusts.gust_torque, check.gust_torque);
  EXPECT_EQ(gusts.gust_force, check.gust_force);
  EXPECT_EQ(gusts.gust_torque_duration, 0.5);
  EXPECT_EQ(gusts.gust_force_duration, 0.2);
  EXPECT_NEAR(realAirGusts(e, *big).gust_force / gusts.gust_force, 4.0, 1e-12);

  const std::vector<EpisodeStart> starts = episodeStarts(e, small.get());
  const HoverControllerParams hand;
  for (const EpisodeStart& start : starts) {
    EXPECT_TRUE(start.force_link == "wing_left_spar" || start.force_link == "wing_right_spar")
        << start.force_link;
  }
  const EpisodeStart& start = starts[1];
  HoverControllerParams c = hand;
  c.altitude = *start.altitude;
  HoverFlightParams f = hoverEpisodeFlight(e, start, c.altitude);
  f.gusts = gusts;
  f.gust_start = start;
  const HoverFlightResult episode = runHoverEpisode(small, hand, e, start);
  const HoverFlightResult by_hand = flyHover(small, c, f);
  EXPECT_EQ(episode.lowest_upright, by_hand.lowest_upright);
  EXPECT_EQ(episode.lowest_height, by_hand.lowest_height);
  EXPECT_EQ(episode.positive_power, by_hand.positive_power);
  EpisodeParams calm = e;
  calm.real_air = false;
  EXPECT_NE(runHoverEpisode(small, hand, calm, start).lowest_upright, episode.lowest_upright);

  // --gust-torque 0 and --gust-force 0 take real air's impulses away (no other size: theirs
  // follow each body): the episode is then the flight with none, its other air the same.
  const EpisodeParams no_impulses =
      evaluationSpecFromArgs({"--preset", "hover", "--real-air", "--gust-torque", "0",
                              "--gust-force", "0", "--episodes", "3", "--duration", "6", "--settle",
                              "3", "--seed", "4"})
          .episode;
  EXPECT_FALSE(no_impulses.real_air_torque);
  EXPECT_FALSE(no_impulses.real_air_push);
  EXPECT_EQ(realAirGusts(no_impulses, *big).gust_torque, 0.0);
  EXPECT_EQ(realAirGusts(no_impulses, *big).gust_force, 0.0);
  HoverFlightParams none = f;
  none.gusts = realAirGusts(no_impulses, *small);
  EXPECT_EQ(runHoverEpisode(small, hand, no_impulses, start).lowest_upright,
            flyHover(small, c, none).lowest_upright);
  EXPECT_NE(runHoverEpisode(small, hand, no_impulses, start).lowest_upright,
            episode.lowest_upright);
}

// --wind and --turbulence with --real-air are its air (flight_check --real-air's rule): the
// issue's moderate turbulence and 2 m/s wind, the impulses, noises and gyro bias real air's.
TEST(HoverEvolution, RealAirTakesAGivenWindAndTurbulenceAndKeepsTheRest) {
  const std::vector<std::string> args = {"--preset", "morph",      "--real-air", "--episodes",
                                         "3",        "--duration", "6",          "--settle",
                                         "3",        "--seed",     "4"};
  std::vector<std::string> moderate_args = args;
  moderate_args.insert(moderate_args.end(), {"--wind", "2", "2", "--turbulence", "moderate"});
  const EpisodeParams real = evaluationSpecFromArgs(args).episode;
  const EpisodeParams moderate = evaluationSpecFromArgs(moderate_args).episode;
  EXPECT_TRUE(moderate.real_air_torque);
  EXPECT_TRUE(moderate.real_air_push);
  EXPECT_EQ(moderate.min_wind, 2.0);
  EXPECT_EQ(moderate.max_wind, 2.0);
  EXPECT_EQ(moderate.world.air.turbulence.wind_at_6m, turbulenceLevelWind("moderate"));
  EXPECT_EQ(moderate.imu_noise.orientation, 0.05);
  EXPECT_EQ(moderate.gyro_bias, 0.02);
  EXPECT_EQ(moderate.altitude_noise, 0.05);
  const CreatureModelPtr small = parseCreatureModel(makeHoverUrdf("light", HoverParams()));
  EXPECT_EQ(realAirGusts(moderate, *small).gust_force, realAirGusts(real, *small).gust_force);
  EXPECT_EQ(realAirGusts(moderate, *small).gust_torque, realAirGusts(real, *small).gust_torque);
  const Vec3 windy = episodeStarts(moderate, small.get())[1].wind;
  const Vec3 calm = episodeStarts(real, small.get())[1].wind;
  EXPECT_NEAR(windy.norm(), 2.0, 1e-12);
  EXPECT_NEAR(calm.norm(), 1.0, 1e-12);
  EXPECT_LT((windy - 2.0 * calm).norm(), 1e-12);  // the same heading drawn
}

// --init: the hand-designed gains file (config/hover_1_hand_gains.yaml, written by
// flight_check --hover --write-gains) is the genome of zeros; a flap network's weights file is
// refused by its key.
TEST(HoverEvolution, InitSeedsFromAGainsFileAndRefusesAWeightsFile) {
  const std::string dir = FLAPSIM_SOURCE_DIR;
  std::optional<EvolveCheckpoint> resume;
  const EvolveOptions o = resolveEvolveOptions(
      {"--preset", "hover", "--init", dir + "/config/hover_1_hand_gains.yaml"}, 1, resume);
  EXPECT_EQ(o.params.ga.initial_genes, std::vector<double>(kHoverGeneCount, 0.0));
  EXPECT_EQ(o.weights_path, "evolve_out/gains.yaml");
  EXPECT_EQ(message([&] {
              resolveEvolveOptions(
                  {"--preset", "hover", "--init", dir + "/config/afc_1_weights.yaml"}, 1, resume);
            }),
            dir + "/config/afc_1_weights.yaml: unknown key 'flap_unit_controller'");
}

TEST(HoverGains, AFileReadsBackBitForBitAndBadOnesAreRefusedByKey) {
  HoverControllerParams p = hoverParamsFromGenes({0.1, -0.2, 0.3, -0.4, 0.5, -0.6, 0.7, -0.8, 0.9,
                                                  -1.0, 0.11, 0.13, -0.17, 0.19, 0.23, -0.29});
  const HoverControllerParams back = hoverGainsFromYaml(hoverGainsToYaml(p, "a header"), "f");
  for (const HoverParamField& f : hoverParamFields()) EXPECT_EQ(back.*f.member, p.*f.member);
  EXPECT_EQ(message([] { hoverGainsFromYaml("height_gain: 4\nheigth_gain: 3\n", "f.yaml"); }),
            "f.yaml: unknown key 'heigth_gain'");
  // A key given twice: yaml-cpp keeps both, a lookup would find the first.
  EXPECT_EQ(message([] { hoverGainsFromYaml("roll_gain: 1\nroll_gain: 2\n", "f.yaml"); }),
            "f.yaml: key 'roll_gain' given twice");
  EXPECT_EQ(message([] { hoverGainsFromYaml("roll_gain: .nan\n", "f.yaml"); }),
            "f.yaml: 'roll_gain' is not finite");
  EXPECT_EQ(message([] { hoverGainsFromYaml("roll_gain: fast\n", "f.yaml"); }),
            "f.yaml: 'roll_gain' is not a number");
  EXPECT_EQ(message([] { hoverGainsFromYaml("trim_frequency: -2\n", "f.yaml"); }),
            "f.yaml: trim_frequency must be > 0");
  EXPECT_EQ(message([] { hoverGainsFromYaml("[1, 2]", "f.yaml"); }),
            "f.yaml: not a map of hover controller gains");
}

}  // namespace
}  // namespace flapsim
