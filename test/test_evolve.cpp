// Flight episodes, the fitness, the evolution, and the committed controllers in flight: the
// evolved one of the one-pair creature (config/afc_1_weights.yaml) and the chains' (the same
// network with the chain pitch term, config/afc_<n>_weights.yaml).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "flapsim/evolve.h"
#include "flapsim/evolve_args.h"
#include "flapsim/evolve_tool.h"
#include "flapsim/flight_check.h"
#include "flapsim/make_creature.h"
#include "flapsim/text_file.h"

namespace flapsim {
namespace {

const std::string kWeights = std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_1_weights.yaml";

CreatureModelPtr creature(int pairs) {
  return parseCreatureModel(makeCreatureUrdf(pairs, "afc"), "afc" + std::to_string(pairs));
}

TEST(Episodes, StartsAreSeededAndAlternateTheirRoll) {
  EpisodeParams p;
  p.episodes = 6;
  p.seed = 9;
  const auto a = episodeStarts(p), b = episodeStarts(p);
  ASSERT_EQ(a.size(), 6u);
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].roll, b[k].roll);
    EXPECT_EQ(a[k].pitch, b[k].pitch);
    EXPECT_GE(std::abs(a[k].roll), p.min_roll);
    EXPECT_LE(std::abs(a[k].roll), p.max_roll);
    EXPECT_EQ(a[k].roll > 0.0, k % 2 == 0) << k;
    EXPECT_LE(std::abs(a[k].pitch), p.max_pitch);
  }
  p.seed = 10;
  EXPECT_NE(episodeStarts(p)[0].roll, a[0].roll);
}

// The robust preset's draws: start rates within +-1 rad/s, gusts horizontal and at most
// 1 m/s in the first half of the episode, step sizes from the list (both seen in 16
// episodes), all the same again from the same seed; the paper's starts are not changed by
// them.
TEST(Episodes, RobustDrawsStayInTheirRangesAndAreSeeded) {
  EpisodeParams p = robustPreset().episode;
  p.episodes = 16;
  p.seed = 5;
  const CreatureModelPtr unit = creature(1);
  const auto a = episodeStarts(p, unit.get()), b = episodeStarts(p, unit.get());
  int small_steps = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].wind.z(), 0.0);
    EXPECT_LE(a[k].wind.norm(), p.max_wind);
    EXPECT_GE(a[k].torque_time, p.gust_window_start * p.duration);
    EXPECT_LE(a[k].torque_time, p.gust_window_end * p.duration);
    EXPECT_GE(a[k].force_time, p.gust_window_start * p.duration);
    EXPECT_LE(a[k].force_time, p.gust_window_end * p.duration);
    EXPECT_TRUE(a[k].force_link == "unit0_wing_left" || a[k].force_link == "unit0_wing_right")
        << a[k].force_link;
    ASSERT_TRUE(a[k].altitude.has_value());
    EXPECT_GE(*a[k].altitude, p.min_altitude);
    EXPECT_LE(*a[k].altitude, p.max_altitude);
    EXPECT_EQ(a[k].wind, b[k].wind);
    EXPECT_EQ(a[k].force_link, b[k].force_link);
    EXPECT_LE(a[k].rate.cwiseAbs().maxCoeff(), 1.0);
    EXPECT_EQ(a[k].gust.z(), 0.0);
    EXPECT_LE(a[k].gust.norm(), 1.0);
    EXPECT_GE(a[k].gust_time, 0.0);
    EXPECT_LE(a[k].gust_time, 0.5 * p.duration);
    EXPECT_TRUE(a[k].step_size == 0.001 || a[k].step_size == 0.0005) << a[k].step_size;
    small_steps += a[k].step_size == 0.0005;
    EXPECT_EQ(a[k].rate, b[k].rate);
    EXPECT_EQ(a[k].gust, b[k].gust);
    EXPECT_EQ(a[k].noise_seed, b[k].noise_seed);
  }
  EXPECT_GT(small_steps, 0);
  EXPECT_LT(small_steps, 16);
  EpisodeParams paper = paperPreset().episode;
  paper.seed = 5;
  EpisodeParams paper_robust = paper;
  paper_robust.max_gust = 1.0;
  paper_robust.max_start_rate = 1.0;
  EXPECT_EQ(episodeStarts(paper)[3].roll, episodeStarts(paper_robust)[3].roll);
}

// With a flip penalty, a flip ends the episode: the samples left score the height at the
// flip less the penalty. The open-loop unit without ballast (60/10/1.2) rolled 0.3 rad flips
// within 20 s (at 6.8 s); its fitness with a 20 m penalty is (sum of the samples up to the
// flip + the rest x (z at the flip - 20)) / samples, and its flight ends there.
TEST(Episodes, AFlipEndsTheEpisodeAtThePenalty) {
  EpisodeParams p;
  p.duration = 20.0;
  FlapUnitParams no_ballast;
  no_ballast.body_com_drop = 0.0;
  const auto unit = parseCreatureModel(makeCreatureUrdf(1, "afc", no_ballast), "no ballast");
  const OpenLoopWingController open(StrokeCommand{60, 10, 1.2});
  const EpisodeResult free_run = runEpisode(unit, open, 0.02, p, attitudeStart(0.3, 0.0), true);
  ASSERT_TRUE(free_run.flipped) << "min up " << free_run.min_upright;
  size_t flip = 0;
  while (free_run.trace[flip].upright >= 0.0) ++flip;
  double before = 0.0;
  for (size_t i = 0; i < flip; ++i) before += free_run.trace[i].height;
  p.flip_penalty = 20.0;
  const EpisodeResult penalised = runEpisode(unit, open, 0.02, p, attitudeStart(0.3, 0.0));
  EXPECT_TRUE(penalised.flipped);
  const double n = static_cast<double>(free_run.trace.size());
  const double expected = (before + (n - flip) * (free_run.trace[flip].height - 20.0)) / n;
  EXPECT_NEAR(penalised.fitness, expected, 1e-9);
  EXPECT_EQ(penalised.final_height, free_run.trace[flip].height);
}

// The root below crash_height (the scenarios' ground, 0) ends the episode as a flip does:
// (sum of the samples before + the rest x (z there - 20)) / samples. A unit whose wings barely
// move falls from 1 m; it cannot reach the ground before free fall does, sqrt(2 h / g).
TEST(Episodes, ACrashBelowTheGroundEndsTheEpisodeAtThePenalty) {
  EpisodeParams p;
  p.duration = 5.0;
  const OpenLoopWingController weak(StrokeCommand{5, 5, 0.1});
  const EpisodeResult fall = runEpisode(creature(1), weak, 0.02, p, attitudeStart(0.05, 0.0), true);
  size_t crash = 0;
  while (crash < fall.trace.size() && fall.trace[crash].height >= 0.0) ++crash;
  ASSERT_LT(crash, fall.trace.size());
  EXPECT_GT(fall.trace[crash].time, std::sqrt(2.0 * p.start_height / 9.81));
  EXPECT_EQ(fall.trace.size(), 250u);  // off by default: the flight goes on below 0
  EXPECT_FALSE(fall.crashed);
  double before = 0.0;
  for (size_t i = 0; i < crash; ++i) before += fall.trace[i].height;
  p.flip_penalty = 20.0;
  p.crash_height = 0.0;
  const EpisodeResult ended =
      runEpisode(creature(1), weak, 0.02, p, attitudeStart(0.05, 0.0), true);
  EXPECT_TRUE(ended.crashed);
  EXPECT_FALSE(ended.flipped);
  EXPECT_EQ(ended.trace.size(), crash);  // the crashing sample ends it unrecorded
  EXPECT_EQ(ended.final_height, fall.trace[crash].height);
  const double n = static_cast<double>(fall.trace.size());
  EXPECT_NEAR(ended.fitness, (before + (n - crash) * (fall.trace[crash].height - 20.0)) / n, 1e-9);
  // Refused by name: a crash without a penalty to end it with, and a height that is no number.
  p.flip_penalty = 0.0;
  EXPECT_EQ(validateEpisodeParams(p),
            "crash_height needs flip_penalty > 0 (a crash ends the episode as a flip does)");
  p.flip_penalty = 20.0;
  p.crash_height = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(validateEpisodeParams(p).find("crash_height must be"), std::string::npos);
  // The robust preset crashes at 0; evolve --crash-height off or H sets it, and its spec says so.
  EXPECT_EQ(robustPreset().episode.crash_height, 0.0);
  const EvolveOptions off = parseEvolveArgs({"--crash-height", "off", "--step-sizes", "0.001"});
  EXPECT_EQ(off.params.episode.crash_height, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(parseEvolveArgs(off.spec_args).params.episode.crash_height,
            -std::numeric_limits<double>::infinity());
  EXPECT_EQ(parseEvolveArgs({"--crash-height", "-2", "--step-sizes", "0.001"})
                .params.episode.crash_height,
            -2.0);
}

TEST(Episodes, FitnessIsTheMeanSampledHeight) {
  EpisodeParams p;
  p.duration = 1.0;
  const OpenLoopWingController open(StrokeCommand{40, 10, 1.2});
  const EpisodeResult r = runEpisode(creature(1), open, 0.02, p, attitudeStart(0.05, 0.0), true);
  ASSERT_EQ(r.trace.size(), 50u);
  double sum = 0.0, max = -1e9;
  for (const auto& s : r.trace) {
    sum += s.height;
    max = std::max(max, s.height);
    ASSERT_EQ(s.downstroke.size(), 2u);
    EXPECT_EQ(s.downstroke[0], 40.0);
  }
  EXPECT_DOUBLE_EQ(r.fitness, sum / 50.0);
  EXPECT_EQ(r.max_height, max);
  EXPECT_EQ(r.final_height, r.trace.back().height);
  EXPECT_NEAR(r.trace.back().time, 1.0, 1e-12);
  // starts at start_height; the body heaves 10 cm in the first 20 ms of the downstroke,
  // against its wings' added mass
  EXPECT_NEAR(r.trace.front().height, 1.0, 0.15);
  // Rolled by 0.05 rad at the start: the root's z axis is tilted by that much.
  EXPECT_NEAR(r.trace.front().upright, std::cos(0.05), 0.01);
  // The lowest up-component over all samples, and over those after settle_time only.
  double lowest = 1.0, lowest_settled = 1.0;
  p.settle_time = 0.5;
  const EpisodeResult q = runEpisode(creature(1), open, 0.02, p, attitudeStart(0.05, 0.0), true);
  for (const auto& s : q.trace) {
    lowest = std::min(lowest, s.upright);
    if (s.time > 0.5 + 1e-9) lowest_settled = std::min(lowest_settled, s.upright);
  }
  EXPECT_EQ(q.min_upright, lowest);
  EXPECT_EQ(q.min_upright_settled, lowest_settled);
  EXPECT_NE(lowest, lowest_settled);  // the two windows differ in this flight
}

TEST(Episodes, BadSetupsAreRefused) {
  EpisodeParams p;
  p.duration = 0.1;
  const OpenLoopWingController open(StrokeCommand{40, 10, 1.2});
  EXPECT_THROW(runEpisode(creature(1), open, 0.0025, p, EpisodeStart()), InputError);
  EXPECT_THROW(runEpisode(creature(1), open, 0.0, p, EpisodeStart()), InputError);
  p.duration = -1.0;
  EXPECT_THROW(runEpisode(creature(1), open, 0.02, p, EpisodeStart()), InputError);
}

TEST(Evolution, ResultsDoNotDependOnTheThreadCountAndTheBestNeverFalls) {
  auto run = [](int threads) {
    EvolveParams p;
    p.ga.population = 4;
    p.ga.generations = 3;
    p.ga.mutation_rate = 0.5;  // so that most children are new and get evaluated
    p.ga.seed = 21;
    p.ga.threads = threads;
    p.episode.duration = 0.6;
    p.episode.episodes = 2;
    return evolveFlapController(p);
  };
  const EvolveResult one = run(1), two = run(2);
  ASSERT_EQ(one.history.size(), 4u);
  ASSERT_EQ(two.history.size(), 4u);
  int evaluated = 0;
  for (size_t g = 0; g < one.history.size(); ++g) {
    EXPECT_EQ(one.history[g].best, two.history[g].best);
    EXPECT_EQ(one.history[g].mean, two.history[g].mean);
    EXPECT_EQ(one.history[g].best_genes, two.history[g].best_genes);
    if (g > 0) {
      EXPECT_GE(one.history[g].best, one.history[g - 1].best);
    }
    evaluated += one.history[g].evaluations;
  }
  EXPECT_GT(evaluated, 4 + 3);  // the children were really flown
  EXPECT_EQ(one.best_weights, two.best_weights);
  // The reported fitness is what the weights fly.
  EpisodeParams episode;
  episode.duration = 0.6;
  episode.episodes = 2;
  episode.seed = evolutionEpisodeSeed(21);
  EXPECT_EQ(one.best_fitness,
            flapFitness(creature(1), FlapControllerParams(), one.best_weights, episode));
}

// ---- The committed evolved controller ----------------------------------------------------

// Held-out start attitudes: drawn from another seed than the ones the
// weights were evolved on (evolutionEpisodeSeed(1)).
EpisodeParams heldOut(double duration, int episodes) {
  EpisodeParams p;
  p.duration = duration;
  p.episodes = episodes;
  p.seed = 20240611;
  return p;
}

// Upright (body z axis never more than 60 deg from vertical) and climbing (at
// least 2 m higher at the end, 1 m higher on average) over the whole flight.
bool uprightAndClimbing(const EpisodeResult& r, double start_height) {
  return r.min_upright > 0.5 && r.final_height > start_height + 2.0 &&
         r.fitness > start_height + 1.0;
}

// Held-out starts of the flight check: roll and pitch uniform in +-15 deg.
EpisodeParams heldOutTilted(double duration, int episodes) {
  EpisodeParams p = heldOut(duration, episodes);
  p.min_roll = 0.0;
  p.max_roll = 0.26;
  p.max_pitch = 0.26;
  return p;
}

// A controller that always gives the network's output for a level unit.
struct LevelOutput : WingController {
  WingPairCommand c;
  std::vector<StrokeCommand> commands(const FlapSensing& sensed) const override {
    std::vector<StrokeCommand> out;
    for (size_t i = 0; i < sensed.orientations.size(); ++i) {
      out.push_back(c.left);
      out.push_back(c.right);
    }
    return out;
  }
};

// From 8 held-out starts tilted up to 15 deg in roll and pitch, 30 s at 1 ms: the network
// keeps the unit upright (up-component above 0.5 throughout) and climbing (2 m above the
// start at the end); its own output for a level unit, held fixed, flips in every one: the
// balance is the network's feedback, not a lucky constant stroke.
TEST(EvolvedController, FliesFromHeldOutStartsWhereItsLevelOutputFlips) {
  const ControllerSpec spec = loadControllerYaml(kWeights);
  const AnnWingController ann(FlapUnitController(spec.params, spec.weights));
  LevelOutput level;
  level.c = FlapUnitController(spec.params, spec.weights).command(Quat::Identity());
  const EpisodeParams p = heldOutTilted(30.0, 8);
  const auto model = creature(1);
  int network_ok = 0, level_flips = 0;
  for (const EpisodeStart& start : episodeStarts(p)) {
    const EpisodeResult r = runEpisode(model, ann, spec.params.control_period, p, start);
    const EpisodeResult o = runEpisode(model, level, spec.params.control_period, p, start);
    std::printf("roll %+.3f pitch %+.3f: network final %.2f m, min up %.3f; level output %s\n",
                start.roll, start.pitch, r.final_height, r.min_upright,
                o.flipped ? "flips" : "does not flip");
    network_ok += !r.flipped && uprightAndClimbing(r, p.start_height);
    level_flips += o.flipped;
  }
  EXPECT_EQ(network_ok, 8);
  EXPECT_EQ(level_flips, 8);
}

// The flight check (flight_check's core) at 1, 0.5 and 0.25 ms: 8 held-out starts of 30 s
// each, every one without a flip, up-component never below 0.5, ending above its start.
TEST(EvolvedController, FlightCheckPassesAtEveryStepSize) {
  const ControllerSpec spec = loadControllerYaml(kWeights);
  for (double dt : {0.001, 0.0005, 0.00025}) {
    FlightCheckParams p;
    p.starts = 8;
    p.duration = 30.0;
    p.step_size = dt;
    p.threads = 2;
    const std::vector<FlightCheckRun> runs = flightCheck(creature(1), spec, p);
    ASSERT_EQ(runs.size(), 8u);
    for (const FlightCheckRun& r : runs) {
      EXPECT_TRUE(r.passed(p.start_height))
          << "step " << dt << " roll " << r.start.roll << " pitch " << r.start.pitch << ": flipped "
          << r.flipped << ", min up " << r.min_upright << ", final " << r.final_height;
      EXPECT_EQ(r.upright_fraction, 1.0);
    }
  }
}

// A flock of 8 one-pair creatures in one world (flock.launch count:=8), each flown by the
// committed network from its own held-out start (up to 15 deg), 60 s at 1, 0.5 and 0.25 ms:
// none flips, none tilts beyond 60 deg, each ends more than 20 m above its start.
TEST(EvolvedController, AFlockOfEightFliesInOneWorldAtEveryStepSize) {
  const ControllerSpec spec = loadControllerYaml(kWeights);
  const FlapUnitController unit(spec.params, spec.weights);
  const auto model = creature(1);
  const int body = model->findLink("unit0_body");
  EpisodeParams p = heldOutTilted(60.0, 8);
  const std::vector<EpisodeStart> starts = episodeStarts(p);
  for (double step : {0.001, 0.0005, 0.00025}) {
    WorldParams wp;
    wp.ground = false;
    wp.step_size = step;
    World world(wp);
    for (int i = 0; i < 8; ++i) {
      world.spawn("afc" + std::to_string(i), model,
                  poseFromXyzRpy(Vec3(1.5 * (i % 4), 1.5 * (i / 4), 1.0),
                                 Vec3(starts[i].roll, starts[i].pitch, 0.0)));
    }
    std::vector<double> lowest_up(8, 1.0);
    const int steps = static_cast<int>(std::lround(spec.params.control_period / step));
    for (int k = 0; k < static_cast<int>(std::lround(60.0 / spec.params.control_period)); ++k) {
      for (int i = 0; i < 8; ++i) {
        const std::string name = "afc" + std::to_string(i);
        const WingPairCommand c = unit.command(world.state(name).link_poses[body].orientation);
        world.setWingCommands(name, {}, {c.left, c.right});
      }
      world.step(steps);
      for (int i = 0; i < 8; ++i) {
        const Quat q = world.rootPose("afc" + std::to_string(i)).orientation;
        lowest_up[i] = std::min(lowest_up[i], (q * Vec3::UnitZ()).z());
      }
    }
    for (int i = 0; i < 8; ++i) {
      const double z = world.rootPose("afc" + std::to_string(i)).position.z();
      std::printf("step %g s, afc%d: lowest up %.3f, at 60 s z = %.2f m\n", step, i, lowest_up[i],
                  z);
      EXPECT_GT(lowest_up[i], 0.5) << step << " s, afc" << i;
      EXPECT_GT(z, 1.0 + 20.0) << step << " s, afc" << i;
    }
  }
}

TEST(EvolvedController, ARightRollGetsARelativelyStrongerRightDownstroke) {
  // The network's right-minus-left downstroke rate never falls as the unit rolls further to
  // the right (right wing low: world_up . body_left > 0), nose up, level or down, and is
  // more than 10 rad/s larger rolled 17 deg right than 17 deg left (13.0: +7.2 against
  // -5.8): the faster (phase-locked) wing lifts its side.
  const ControllerSpec spec = loadControllerYaml(kWeights);
  ASSERT_TRUE(spec.params.phase_lock);
  const FlapUnitController c(spec.params, spec.weights);
  auto difference = [&](double forward_up, double wing_up) {
    const std::vector<double> r = c.rates({forward_up, wing_up});
    return r[0] - r[1];
  };
  for (double forward_up : {-0.2, 0.0, 0.2}) {
    double last = difference(forward_up, -0.4);
    for (double wing_up : {-0.2, -0.1, 0.0, 0.1, 0.2, 0.4}) {
      const double d = difference(forward_up, wing_up);
      EXPECT_GE(d, last) << "forward_up " << forward_up << ", wing_up " << wing_up;
      last = d;
    }
  }
  EXPECT_GT(difference(0.0, 0.3), difference(0.0, -0.3) + 10.0);
}

// The committed controller of the `pairs`-unit chain: the one-pair network with the chain
// pitch term.
ControllerSpec chainController(int pairs) {
  return loadControllerYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_" +
                            std::to_string(pairs) + "_weights.yaml");
}

// How many of flight_check's first 8 held-out starts `model` flies for 60 s at 1 ms under
// `spec` (FlightCheckRun::passed: no flip, up-component never below 0.5, ending above its
// start), in the air whose added mass does `products`.
int flownOfEightStarts(const CreatureModelPtr& model, const ControllerSpec& spec,
                       AddedMassProducts products = AirParams().added_mass_products) {
  FlightCheckParams p;
  p.starts = 8;
  p.threads = 2;
  p.added_mass_products = products;
  const std::vector<FlightCheckRun> runs = flightCheck(model, spec, p);
  return static_cast<int>(std::count_if(
      runs.begin(), runs.end(), [&](const FlightCheckRun& r) { return r.passed(p.start_height); }));
}

// flownOfEightStarts() of the `pairs`-unit chain (urdf/afc_<n>.urdf's creature) under its
// committed controller, flown once per test run: several tests compare against it.
int chainFlownOfEightStarts(int pairs) {
  static std::map<int, int> flown;
  auto it = flown.find(pairs);
  if (it == flown.end()) {
    it = flown.emplace(pairs, flownOfEightStarts(creature(pairs), chainController(pairs))).first;
  }
  return it->second;
}

// The paper flies creatures of 4, 6 and 12 pairs with the flap unit's network on every unit
// (Fig. 10-12). With the chain pitch term on top (config/afc_<n>_weights.yaml, set with the
// products omitted) and units joined by sprung roll joints (urdf/afc_<n>.urdf), the chains of
// 4 and 6 fly each of flight_check's first 8 held-out starts for 60 s at 1 ms, and the chain of
// 12 all but one at most (measured in the default air: 8, 8 and 7; with the products omitted:
// 8, 8 and 8).
TEST(EvolvedController, ChainsOf4And6PairsFlyEveryHeldOutStartAndOf12AllButOne) {
  for (int pairs : {4, 6, 12}) {
    const int flown = chainFlownOfEightStarts(pairs);
    std::printf("%2d pairs: %d of 8 starts flown\n", pairs, flown);
    EXPECT_GE(flown, pairs == 12 ? 7 : 8) << pairs << " pairs";
  }
}

// Why the pitch term was set: every unit's network sees the same pitch, so the network alone
// cannot right the 12-unit chain, rigid in pitch. With the products omitted it flies 7 of
// those 8 starts (the others pitch over and sink, or flip), against 8 with the term. In the
// default air, where the products are shed, the network alone flies as many as with the term
// (7 and 7, measured 7 December 2026): the term answered the omitted air's pitching, and is
// kept only as the committed files' setting. The flights are chaotic (a change of rounding
// moved the omitted air's count alone from 4 to 6): held are the orderings.
TEST(EvolvedController, ThePitchTermHelpsTheTwelveUnitChainOnlyWithTheProductsOmitted) {
  ControllerSpec spec = chainController(12);
  ASSERT_GT(spec.params.pitch_gain, 0.0);
  const AddedMassProducts omitted = AddedMassProducts::kOmitted;
  const int with_term = chainFlownOfEightStarts(12);
  const int omitted_with_term = flownOfEightStarts(creature(12), spec, omitted);
  spec.params.pitch_gain = 0.0;
  const int alone = flownOfEightStarts(creature(12), spec);
  const int omitted_alone = flownOfEightStarts(creature(12), spec, omitted);
  std::printf(
      "12 units, 8 starts: %d flown with the pitch term, %d without; products omitted: %d "
      "and %d\n",
      with_term, alone, omitted_with_term, omitted_alone);
  EXPECT_EQ(omitted_with_term, 8);
  EXPECT_LT(omitted_alone, omitted_with_term);
  EXPECT_GE(alone, with_term);
}

// Why the springs between units (make_creature's default 2 N m/rad): without them one unit's
// roll excursion twists the chain, its units beat at different mean rates and pitch it, and
// the 6-unit chain under its network, within the paper's rate limit (60 rad/s; the pitch term
// up to 75; IMU read unfiltered), flies fewer of those 8 starts: 7 with each unit's attitude
// sensed from the root's IMU and the encoders (5 when it was read exact from the world; none
// with strip theory's added mass), against 8 with them. With the committed file's headroom
// (80 rad/s) the unsprung chain flies all 8 too (measured), so the limits are set here. The
// flights are chaotic: a start is won or lost on a rounding difference, so only the ordering is
// claimed.
// Measured again once the physics no longer depended on the observer (the angular momentum
// carried across a step had taken Bullet's error in the centre's displacement crossed with the
// momentum): with the products omitted the unsprung chain flies all 8 as well. In the default
// air, the products shed, the paper's rate limit is tight for the chain: 4 of the 8 with the
// springs, 1 without (measured 7 December 2026; the committed file's 80 rad/s flies all 8).
// Held here: the springs fly more of them.
TEST(EvolvedController, UnderThePapersRateLimitTheSixUnitChainFliesMoreStartsWithLinkSprings) {
  ControllerSpec spec = chainController(6);
  spec.params.max_downstroke_rate = 60.0;
  spec.params.pitch_max_downstroke_rate = 75.0;
  spec.params.attitude_filter_time = 0.0;
  FlapUnitParams unit;
  ASSERT_EQ(unit.link_stiffness, 2.0);
  unit.link_stiffness = 0.0;
  const auto free = parseCreatureModel(makeCreatureUrdf(6, "afc6", unit), "unsprung afc6");
  const int sprung_flown = flownOfEightStarts(creature(6), spec);
  const int free_flown = flownOfEightStarts(free, spec);
  std::printf("6 units, 8 starts, paper's rate limit: %d flown with springs, %d without\n",
              sprung_flown, free_flown);
  EXPECT_GT(sprung_flown, free_flown);
}

// Why roll joints: with wave 1's pitch joints (springs of 0.5 N m/rad, rigid in roll) the
// 6-unit chain flies 3 of those 8 starts under the one-pair network (the pitch term has no
// rigid chain to pitch there); the roll-jointed chain under its controller flies all 8.
TEST(EvolvedController, RollJointsFlyASixUnitChainWherePitchJointsFail) {
  FlapUnitParams unit;
  unit.link_axis = LinkAxis::kPitch;
  unit.link_stiffness = 0.5;
  const auto pitch_jointed =
      parseCreatureModel(makeCreatureUrdf(6, "afc6", unit), "pitch-jointed afc6");
  const int pitch = flownOfEightStarts(pitch_jointed, loadControllerYaml(kWeights));
  const int roll = chainFlownOfEightStarts(6);
  std::printf("6 units, 8 starts: %d flown with pitch joints, %d with roll joints\n", pitch, roll);
  EXPECT_LE(pitch, 4);
  EXPECT_EQ(roll, 8);
}

// A 1 N push on a wing for 0.2 s (4.4 times the unit's weight, about 0.2 N m of roll) flips
// the altitude controller's unit in most of flight_check's 20 held-out starts when its network
// flies alone: the network steers only the downstroke rates, its upstrokes stay near 10 rad/s.
// With the roll reflex (config/afc_1_altitude_weights.yaml: fast upstrokes on the high wing,
// fast downstrokes on the low one while the unit rolls over) one does at most. 30 s flights
// (the push at 3-18 s), 1 ms, with the products omitted (the air it was evolved in): 13 flips
// without, 0 with (60 s flights: 11 and 0). In the default air, the products shed: 5 without,
// 0 with (measured 7 December 2026).
TEST(EvolvedController, TheRollReflexCutsTheFlipsOfAWingPushToOneAtMost) {
  ControllerSpec spec =
      loadControllerYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_1_altitude_weights.yaml");
  ASSERT_GT(spec.params.roll_reflex_bank, 0.0);
  FlightCheckParams p;
  p.starts = 20;
  p.max_roll = p.max_pitch = 0.52;
  p.duration = 30.0;
  p.gust_force = 1.0;
  p.gust_time = 0.2;
  p.threads = 2;
  auto flips = [&](const ControllerSpec& c, AddedMassProducts products) {
    p.added_mass_products = products;
    const std::vector<FlightCheckRun> runs = flightCheck(creature(1), c, p);
    return std::count_if(runs.begin(), runs.end(),
                         [](const FlightCheckRun& r) { return r.flipped; });
  };
  const AddedMassProducts shed = AddedMassProducts::kShed, omitted = AddedMassProducts::kOmitted;
  const long with_reflex = flips(spec, shed), omitted_with_reflex = flips(spec, omitted);
  spec.params.roll_reflex_bank = 0.0;
  const long net_alone = flips(spec, shed), omitted_alone = flips(spec, omitted);
  std::printf(
      "1 N wing push, 20 starts: %ld flips with the roll reflex, %ld without; products omitted: "
      "%ld and %ld\n",
      with_reflex, net_alone, omitted_with_reflex, omitted_alone);
  EXPECT_LE(with_reflex, 1);
  EXPECT_GE(net_alone, 4);
  EXPECT_LE(omitted_with_reflex, 1);
  EXPECT_GE(omitted_alone, 10);
}

// flight_check's table conditions (20 held-out starts within +-0.52 rad) holding 5 m for
// `duration` s, the disturbance left to the caller.
FlightCheckParams tableHolding5m(double duration) {
  FlightCheckParams p;
  p.starts = 20;
  p.max_roll = p.max_pitch = 0.52;
  p.duration = duration;
  p.altitude = 5.0;
  return p;
}

// The level start (roll and pitch 0) holding 5 m for 60 s: flight_check --roll 0 --pitch 0
// --starts 1 --altitude 5.
FlightCheckParams levelStartHolding5m() {
  FlightCheckParams p = tableHolding5m(60.0);
  p.starts = 1;
  p.max_roll = p.max_pitch = 0.0;
  return p;
}

// One episode of `creature` under the network of `spec`, at its control period.
EpisodeResult flyNetwork(const CreatureModelPtr& creature, const ControllerSpec& spec,
                         const EpisodeParams& e, const EpisodeStart& start) {
  const AnnWingController ann(FlapUnitController(spec.params, spec.weights));
  return runEpisode(creature, ann, spec.params.control_period, e, start);
}

// The 12-unit chain holding 5 m in a 1 m/s wind (flight_check's held-out start 13 of 20,
// config/afc_12_altitude_weights.yaml): with the products omitted, without the chain pitch
// reflex it pitches over with its pitch term pinned and sinks below its 1 m start within 20 s
// (-2.0 m at 20 s, measured 7 December 2026; of the 20 starts 5 sank without the reflex, none
// with it); with it, it is at 5 m (5.08 m) at 20 s, upright. In the default air, the products shed,
// it holds 5 m either way (5.15 m with the reflex, 5.02 m without, measured 7 December 2026): the
// reflex answered the omitted air.
TEST(EvolvedController, ThePitchReflexKeepsTheChainUpInWindOnlyWithTheProductsOmitted) {
  ControllerSpec spec =
      loadControllerYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_12_altitude_weights.yaml");
  ASSERT_GT(spec.params.pitch_reflex_angle, 0.0);
  FlightCheckParams p = tableHolding5m(20.0);
  p.wind = 1.0;
  const EpisodeParams e = flightCheckEpisodes(p);
  p.added_mass_products = AddedMassProducts::kOmitted;
  const EpisodeParams omitted = flightCheckEpisodes(p);
  const CreatureModelPtr chain = creature(12);
  const EpisodeStart start = episodeStarts(e, chain.get()).at(13);
  const EpisodeResult with_reflex = flyNetwork(chain, spec, e, start);
  const EpisodeResult omitted_with = flyNetwork(chain, spec, omitted, start);
  spec.params.pitch_reflex_angle = 0.0;
  const EpisodeResult without = flyNetwork(chain, spec, e, start);
  const EpisodeResult omitted_without = flyNetwork(chain, spec, omitted, start);
  std::printf(
      "12 units, 1 m/s wind, hold 5 m: %.2f m at 20 s with the pitch reflex, %.2f m "
      "without; products omitted: %.2f and %.2f m\n",
      with_reflex.final_height, without.final_height, omitted_with.final_height,
      omitted_without.final_height);
  EXPECT_FALSE(with_reflex.flipped);
  EXPECT_FALSE(without.flipped);
  EXPECT_NEAR(with_reflex.final_height, 5.0, 0.3);
  EXPECT_NEAR(without.final_height, 5.0, 0.3);
  EXPECT_NEAR(omitted_with.final_height, 5.0, 0.3);
  EXPECT_LT(omitted_without.final_height, p.start_height);
}

// The 12-unit chain holding 5 m with 0.1 rad of attitude noise (and 0.1 rad/s on the gyro) on
// its root's IMU (flight_check's held-out starts 13 and 15 of 20, 20 s each,
// config/afc_12_altitude_weights.yaml): the noise reaches every unit's input at once through the
// encoders. Once settled (10-20 s), read raw the root unit rocks down to an up-component of 0.533
// (58 deg) in the worse of the two; through the weights file's attitude filter (0.1 s), to 0.734
// (43 deg) (measured: 0.734 / 0.971 against 0.533 / 0.617; over all 20 starts the filtered
// chain's lowest is higher in 14, and 0.631 against 0.533 at worst). The first seconds, where the
// tilted starts right themselves, are left out: there the start, not the noise, sets the lowest
// up-component.
// On the physics that no longer depends on the observer, with the products omitted, the raw
// reading rocked the chain far less (0.698 against the filter's 0.717). In the default air, the
// products shed, the filter matters again: 0.728 filtered, 0.379 raw (measured 7 December
// 2026). Held here: filtered above 0.65, raw below 0.5.
TEST(EvolvedController, TheAttitudeFilterKeepsTheChainUnderNoiseAbove065WhereRawItRocksBelow05) {
  ControllerSpec spec =
      loadControllerYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_12_altitude_weights.yaml");
  ASSERT_GT(spec.params.attitude_filter_time, 0.0);
  FlightCheckParams p = tableHolding5m(20.0);
  p.noise = 0.1;
  const EpisodeParams e = flightCheckEpisodes(p);
  const CreatureModelPtr chain = creature(12);
  const std::vector<EpisodeStart> starts = episodeStarts(e, chain.get());
  auto lowest = [&](const ControllerSpec& c) {
    double low = 1.0;
    for (int k : {13, 15})
      low = std::min(low, flyNetwork(chain, c, e, starts.at(k)).min_upright_settled);
    return low;
  };
  const double filtered = lowest(spec);
  spec.params.attitude_filter_time = 0.0;
  const double raw = lowest(spec);
  std::printf(
      "12 units, 0.1 rad noise, starts 13 and 15, 10-20 s: lowest up %.3f filtered, %.3f raw\n",
      filtered, raw);
  EXPECT_GT(filtered, 0.65);
  EXPECT_LT(raw, 0.5);
}

// The 12-unit chain from a level start in still air holding 5 m for 60 s at 1 ms
// (config/afc_12_altitude_weights.yaml): levelled by attitude alone it keeps what speed it
// picks up along its length and ends 21.4 m from where it rose (measured; a tenth of a degree
// of mean pitch drives it); with the file's ground-speed damping (odometry's velocity leaning
// the up it levels to), 2.56 m.
// On the physics that no longer depends on the observer, with the products omitted, the chain
// levelled by attitude alone drifted 0.34 m (the 21.4 m were the artefact's: the spurious
// angular momentum tilted it), with the damping 1.40 m. In the default air, the products shed,
// the damping drifts it 19.4 m and attitude alone 1.75 m (measured 7 December 2026): the
// damping, set by hand in the omitted air, now harms this start. Held here: within 3 m without
// it, beyond 10 m with it.
TEST(EvolvedController, TheGroundSpeedDampingDriftsTheChainsLevelStartThatStaysWithin3mWithout) {
  ControllerSpec spec =
      loadControllerYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_12_altitude_weights.yaml");
  ASSERT_GT(spec.params.velocity_gain, 0.0);
  const EpisodeParams e = flightCheckEpisodes(levelStartHolding5m());
  const CreatureModelPtr chain = creature(12);
  const EpisodeStart level = episodeStarts(e).at(0);  // roll and pitch 0; the setpoint
  ASSERT_EQ(level.roll, 0.0);
  ASSERT_EQ(level.pitch, 0.0);
  const EpisodeResult damped = flyNetwork(chain, spec, e, level);
  spec.params.velocity_gain = 0.0;
  const EpisodeResult levelled = flyNetwork(chain, spec, e, level);
  std::printf(
      "12 units, level start, 60 s: drift %.2f m with ground-speed damping, %.2f m without\n",
      damped.lateral_drift, levelled.lateral_drift);
  EXPECT_FALSE(damped.flipped);
  EXPECT_FALSE(levelled.flipped);
  EXPECT_GT(damped.lateral_drift, 10.0);
  EXPECT_LT(levelled.lateral_drift, 3.0);
}

// The same level start with the ground-speed sensor's noise (flight_check --velocity-noise 0.1:
// 0.1 m/s per axis, drawn afresh each control period, 0.02 s): the lean is capped at the file's
// 0.01 rad, which 0.05 m/s of noise already reaches, so the noise tilts the level the units hold
// by up to that cap at random. Measured before the observer fix: 4.58 m (0.05 m/s: 4.96 m;
// 0.2 m/s: 4.50 m), against 2.56 m read exactly and 21.4 m without the damping. In the default
// air (7 December 2026): 2.35 m, against 19.4 m read exactly: the noise's random lean breaks
// the exact reading's steady one. A negative noise is refused by name.
TEST(EvolvedController, TheGroundSpeedDampingThroughANoisySensorHoldsTheLevelStartWithin6m) {
  const ControllerSpec spec =
      loadControllerYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_12_altitude_weights.yaml");
  FlightCheckParams p = levelStartHolding5m();
  p.velocity_noise = -0.1;
  EXPECT_THROW(flightCheckEpisodes(p), InputError);
  EpisodeParams e = flightCheckEpisodes(tableHolding5m(60.0));
  e.velocity_noise = -0.1;
  EXPECT_EQ(validateEpisodeParams(e), "velocity_noise must be in [0, 1000] m/s");
  p.velocity_noise = 0.1;
  e = flightCheckEpisodes(p);
  const EpisodeStart level = episodeStarts(e).at(0);
  ASSERT_EQ(level.roll, 0.0);
  const EpisodeResult noisy = flyNetwork(creature(12), spec, e, level);
  std::printf("12 units, level start, 60 s, 0.1 m/s of ground-speed noise: drift %.2f m\n",
              noisy.lateral_drift);
  EXPECT_FALSE(noisy.flipped);
  EXPECT_LT(noisy.lateral_drift, 6.0);
  // The exact sensor's 19.4 m (the test above): the noise reached it.
  const EpisodeResult exact =
      flyNetwork(creature(12), spec, flightCheckEpisodes(levelStartHolding5m()), level);
  EXPECT_GT(exact.lateral_drift - noisy.lateral_drift, 10.0);
}

// evolve --init FILE: the file's weights seed generation 0 if it was flown with the
// evolution's stroke settings; a file flown otherwise (config/afc_1_altitude_weights.yaml: a
// raised stroke, a 65 rad/s cap, a 0.5 m altitude scale) is refused by its key, naming the flag
// that would match it.
TEST(EvolveInit, SeedsTheWeightsOnlyOfAFileFlownWithTheEvolutionsSettings) {
  const std::string flown = std::string(FLAPSIM_SOURCE_DIR) + "/config/afc_1_altitude_weights.yaml";
  ControllerSpec spec = loadControllerYaml(flown);
  std::optional<EvolveCheckpoint> resume;
  // The roll reflex is set by hand: no evolution flies it, so a file with it seeds none.
  ASSERT_GT(spec.params.roll_reflex_bank, 0.0);
  try {
    resolveEvolveOptions(
        {"--init", flown, "--max-rate", "65", "--stroke-offset", "0.1", "--altitude-scale", "0.5"},
        1, resume);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--init: " + flown +
                                         ": its roll_reflex_bank is 0.4, the evolution's 0 (set "
                                         "by hand, not evolved: seed from a file without it)");
  }
  // The same file without it.
  spec.params.roll_reflex_bank = 0.0;
  const std::string file = ::testing::TempDir() + "afc_1_altitude_no_reflex.yaml";
  writeTextFile(file, controllerToYaml(spec));
  const std::vector<std::string> matching = {"--init",          file,  "--max-rate",       "65",
                                             "--stroke-offset", "0.1", "--altitude-scale", "0.5"};
  EXPECT_EQ(resolveEvolveOptions(matching, 1, resume).params.ga.initial_genes, spec.weights);
  try {
    resolveEvolveOptions({"--init", file, "--max-rate", "65", "--altitude-scale", "0.5"}, 1,
                         resume);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--init: " + file +
                                         ": its stroke_offset is 0.1, the evolution's 0 (give "
                                         "--stroke-offset 0.1)");
  }
  try {
    resolveEvolveOptions({"--init", file}, 1, resume);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_downstroke_rate is 65"), std::string::npos)
        << e.what();
  }
  // The settings set by hand, not evolved, are refused by key: the chain pitch reflex, the
  // attitude filter and the ground-speed damping, each alone in a file otherwise matching.
  const ControllerSpec matched = spec;
  auto handSet = [&](const std::string& key, double FlapControllerParams::*setting) {
    ControllerSpec with = matched;
    with.params.*setting = 0.2;
    const std::string path = ::testing::TempDir() + "afc_1_altitude_" + key + ".yaml";
    writeTextFile(path, controllerToYaml(with));
    try {
      resolveEvolveOptions(
          {"--init", path, "--max-rate", "65", "--stroke-offset", "0.1", "--altitude-scale", "0.5"},
          1, resume);
      ADD_FAILURE() << key << ": expected an error";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), "--init: " + path + ": its " + key +
                                           " is 0.2, the evolution's 0 (set by hand, not "
                                           "evolved: seed from a file without it)");
    }
  };
  handSet("pitch_reflex_angle", &FlapControllerParams::pitch_reflex_angle);
  handSet("attitude_filter_time", &FlapControllerParams::attitude_filter_time);
  handSet("velocity_gain", &FlapControllerParams::velocity_gain);
}

}  // namespace
}  // namespace flapsim
