// The episode task as a pure function, evaluators, checkpoints and resume, and the
// evolve flags: whatever evaluates the tasks and wherever a run is resumed, the
// evolution is the same bit for bit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <numeric>
#include <optional>

#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"
#include "flapsim/evolve_tool.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::ReverseEvaluator;

EvolveParams tinyRun() {
  EvolveParams p = robustPreset();
  p.ga.population = 4;
  p.ga.generations = 4;
  p.ga.mutation_rate = 0.5;  // most children are new and get flown
  p.ga.seed = 7;
  p.ga.threads = 2;
  p.episode.duration = 0.6;
  p.episode.episodes = 2;
  return p;
}

void expectSameHistory(const std::vector<GenerationStats>& a,
                       const std::vector<GenerationStats>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t g = 0; g < a.size(); ++g) {
    EXPECT_EQ(a[g].generation, b[g].generation);
    EXPECT_EQ(a[g].best, b[g].best) << g;
    EXPECT_EQ(a[g].mean, b[g].mean) << g;
    EXPECT_EQ(a[g].worst, b[g].worst) << g;
    EXPECT_EQ(a[g].evaluations, b[g].evaluations) << g;
    EXPECT_EQ(a[g].best_genes, b[g].best_genes) << g;
  }
}

TEST(EpisodeRunner, ATaskFliesTheSameAsRunEpisode) {
  const EvolveParams p = tinyRun();
  const EvaluationSpec spec = evaluationSpec(p);
  const EpisodeRunner runner(spec);
  std::vector<double> w(runner.weightCount());
  std::iota(w.begin(), w.end(), -3.0);
  const auto model = parseCreatureModel(makeCreatureUrdf(1, "afc", p.unit), "afc");
  const AnnWingController ann(FlapUnitController(p.controller, w));
  const auto starts = episodeStarts(spec.episode, model.get());
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(runner.evaluate(EpisodeTask{w, k}),
              runEpisode(model, ann, p.controller.control_period, spec.episode, starts[k]).fitness);
  }
  EXPECT_NE(runner.evaluate(EpisodeTask{w, 0}), runner.evaluate(EpisodeTask{w, 1}));
}

TEST(EpisodeRunner, TasksThatDoNotFitTheSpecGetNamedErrors) {
  const EpisodeRunner runner(evaluationSpec(tinyRun()));
  std::vector<double> w(runner.weightCount(), 0.5);
  EXPECT_EQ(runner.check(EpisodeTask{w, 1}), "");
  std::vector<double> short_w(w.begin(), w.end() - 1);
  EXPECT_NE(runner.check(EpisodeTask{short_w, 0}).find("weights, the controller has"),
            std::string::npos);
  EXPECT_THROW(runner.evaluate(EpisodeTask{short_w, 0}), TaskError);
  EXPECT_NE(runner.check(EpisodeTask{w, 2}).find("episode 2 is not in [0, 2)"), std::string::npos);
  EXPECT_THROW(runner.evaluate(EpisodeTask{w, -1}), TaskError);
  w[3] = std::nan("");
  EXPECT_NE(runner.check(EpisodeTask{w, 0}).find("weight 3 is not finite"), std::string::npos);
}

TEST(Evolution, AnEvaluatorAnsweringInAnotherOrderGivesTheSameBits) {
  const EvolveParams p = tinyRun();
  const EvolveResult in_process = evolveFlapController(p);
  ReverseEvaluator reverse(evaluationSpec(p));
  EvolveHooks hooks;
  hooks.evaluator = &reverse;
  const EvolveResult other = evolveFlapController(p, hooks);
  expectSameHistory(in_process.history, other.history);
  EXPECT_EQ(in_process.best_weights, other.best_weights);
  EXPECT_EQ(in_process.best_fitness, other.best_fitness);
  int evaluated = 0;
  for (const auto& g : in_process.history) evaluated += g.evaluations;
  EXPECT_EQ(reverse.tasks_, evaluated * 2);  // every task went through it
}

// evolve --episode-sets 3 with 2 episodes: the runner draws 6; generation g asks for episodes
// 2 (g mod 3) and 2 (g mod 3) + 1 of every individual, the elite and copies too; set 0 is the
// episodes of the run without sets, so generation 0 is that run's to the bit; and an evaluator
// answering in another order (which records the batches) gives the in-process bits.
TEST(EpisodeSets, GenerationGFliesSetGModKWithEveryIndividualAnew) {
  EvolveParams one = tinyRun();
  EvolveParams sets = one;
  sets.episode_sets = 3;
  const EvaluationSpec spec = evaluationSpec(sets);
  EXPECT_EQ(spec.episode.episodes, 6);
  ReverseEvaluator recorder(spec);
  EvolveHooks hooks;
  hooks.evaluator = &recorder;
  const EvolveResult r = evolveFlapController(sets, hooks);
  const EvolveResult in_process = evolveFlapController(sets);
  expectSameHistory(r.history, in_process.history);
  EXPECT_EQ(r.best_weights, in_process.best_weights);
  ASSERT_EQ(recorder.batches_.size(), 6u);  // generations 0-4, one batch each, then all sets
  for (size_t g = 0; g < 5; ++g) {
    const int first = 2 * static_cast<int>(g % 3);
    std::vector<int> expected;
    for (int i = 0; i < sets.ga.population; ++i)
      expected.insert(expected.end(), {first, first + 1});
    EXPECT_EQ(recorder.batches_[g], expected) << "generation " << g;
    EXPECT_EQ(r.history[g].evaluations, sets.ga.population) << "generation " << g;
  }
  const EvolveResult plain = evolveFlapController(one);
  EXPECT_EQ(r.history[0].best, plain.history[0].best);
  EXPECT_EQ(r.history[0].mean, plain.history[0].mean);
  EXPECT_NE(r.history[1].mean, plain.history[1].mean);
  // Then the last generation flies all six episodes; the best over them is the result's.
  std::vector<int> every;
  for (int i = 0; i < sets.ga.population; ++i) every.insert(every.end(), {0, 1, 2, 3, 4, 5});
  EXPECT_EQ(recorder.batches_[5], every);
  const EpisodeRunner runner(spec);
  double best = -1e300;
  std::vector<double> best_genes;
  for (const Individual& ind : r.population) {
    double sum = 0.0;
    for (int k = 0; k < 6; ++k) sum += runner.evaluate(EpisodeTask{ind.genes, k});
    if (sum / 6 > best) {
      best = sum / 6;
      best_genes = ind.genes;
    }
  }
  EXPECT_EQ(r.best_fitness, best);
  EXPECT_EQ(r.best_weights, best_genes);
  EXPECT_NE(r.best_fitness, r.history.back().best);  // not the last set's figure
}

TEST(EpisodeSets, TheSpecCarriesThemAndBadCountsAreRefusedByName) {
  const EvaluationSpec s =
      evaluationSpecFromArgs({"--preset", "robust", "--episodes", "4", "--episode-sets", "3"});
  EXPECT_EQ(s.episode.episodes, 12);
  EXPECT_THROW(evaluationSpecFromArgs({"--preset", "robust", "--episode-sets", "0"}), InputError);
  auto refusal = [](const std::vector<std::string>& args) {
    try {
      evaluationSpecFromArgs(args);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("taken");
  };
  EXPECT_EQ(refusal({"--preset", "robust", "--episodes", "300", "--episode-sets", "4"}),
            "--episodes 300 x --episode-sets 4 is over 1000 episodes");
  EXPECT_EQ(refusal({"--preset", "morph", "--selection", "nsga2", "--population", "4",
                     "--episode-sets", "2"}),
            "--episode-sets 2 is for the elitist GA, not --selection nsga2");
}

// Checkpoints of a run of `p`, resumed from generations 1 and 3, end as the whole run.
void resumeEndsAsTheWholeRun(const EvolveParams& p) {
  std::vector<std::string> texts;
  EvolveHooks hooks;
  hooks.on_checkpoint = [&](const EvolveCheckpoint& c) {
    EXPECT_EQ(c.generation, static_cast<int>(texts.size()));
    texts.push_back(checkpointToText(c));
  };
  const EvolveResult whole = evolveFlapController(p, hooks);
  ASSERT_EQ(texts.size(), 5u);
  for (int k : {1, 3}) {
    const EvolveCheckpoint c = checkpointFromText(texts[k]);
    EXPECT_EQ(checkpointToText(c), texts[k]);  // the text round trip is exact
    EvolveHooks resume;
    resume.resume = &c;
    int generations_run = 0;
    resume.on_generation = [&](const GenerationStats&) { ++generations_run; };
    const EvolveResult rest = evolveFlapController(p, resume);
    EXPECT_EQ(generations_run, 4 - k);
    expectSameHistory(whole.history, rest.history);
    EXPECT_EQ(whole.best_weights, rest.best_weights);
  }
}

// Run 4 generations writing checkpoints; resume from the text of generation 1's and of
// generation 3's: both end as the uninterrupted run, bit for bit; with one set of episodes and
// with three (--episode-sets, each generation on the next set).
TEST(Resume, FromACheckpointEndsBitIdenticalToTheUninterruptedRun) {
  for (int sets : {1, 3}) {
    SCOPED_TRACE(sets);
    EvolveParams p = tinyRun();
    p.episode_sets = sets;
    resumeEndsAsTheWholeRun(p);
  }
}

TEST(Resume, ACheckpointOfAnotherRunOrAMalformedOneIsRefused) {
  EvolveParams p = tinyRun();
  p.ga.generations = 1;
  EvolveCheckpoint last;
  EvolveHooks hooks;
  hooks.on_checkpoint = [&](const EvolveCheckpoint& c) { last = c; };
  evolveFlapController(p, hooks);
  EvolveParams other = p;
  other.ga.seed = 8;
  EvolveHooks resume;
  resume.resume = &last;
  EXPECT_THROW(evolveFlapController(other, resume), std::invalid_argument);
  EvolveParams bigger = p;
  bigger.ga.population = 6;
  EXPECT_THROW(evolveFlapController(bigger, resume), std::invalid_argument);
  std::string text = checkpointToText(last);
  text.replace(text.find("population"), 10, "populace");
  try {
    checkpointFromText(text);
    FAIL() << "a malformed checkpoint was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expected 'population'"), std::string::npos) << e.what();
  }
}

TEST(EvolveArgs, SpecArgsRebuildTheSameSpecAndBadFlagsAreNamed) {
  const EvolveOptions o = parseEvolveArgs({"--preset", "paper", "--seed", "5", "--threads", "3",
                                           "--out", "x", "--farm", "--episodes", "3"});
  EXPECT_TRUE(o.farm);
  EXPECT_EQ(o.params.ga.threads, 3);
  EXPECT_EQ(o.weights_path, "x/weights.yaml");
  EXPECT_EQ(o.spec_args,
            (std::vector<std::string>{"--preset", "paper", "--seed", "5", "--episodes", "3"}));
  const EvaluationSpec a = evaluationSpecFromArgs(o.spec_args);
  const EvaluationSpec b = evaluationSpec(o.params);
  EXPECT_EQ(a.episode.seed, b.episode.seed);
  EXPECT_EQ(a.episode.episodes, 3);
  EXPECT_EQ(a.episode.duration, paperPreset().episode.duration);
  EXPECT_THROW(parseEvolveArgs({"--episodes", "two"}), InputError);
  EXPECT_THROW(parseEvolveArgs({"--bogus", "1"}), InputError);
  EXPECT_THROW(parseEvolveArgs({"--farm-batch", "0"}), InputError);
  EXPECT_THROW(evaluationSpecFromArgs({"--preset", "robust", "--out", "x"}), InputError);
  EXPECT_THROW(evaluationSpecFromArgs({"--preset", "robust", "--episodes", "0"}), InputError);
  // The chain pitch term travels with the spec (to farm workers and checkpoints).
  const EvaluationSpec chain =
      evaluationSpecFromArgs({"--preset", "robust", "--pairs", "4", "--pitch-gain", "1.5"});
  EXPECT_EQ(chain.pairs, 4);
  EXPECT_EQ(chain.controller.pitch_gain, 1.5);
  EXPECT_THROW(evaluationSpecFromArgs({"--preset", "robust", "--pitch-gain", "-1"}), InputError);
}

// Issue 27, case 5: the sample count of a 1e9 s episode overflowed an int, and the run
// "finished" with fitness 0.
TEST(EpisodeLimits, ALongEpisodeIsRefusedNotScoredZero) {
  const EvolveParams p = tinyRun();
  EpisodeParams e = evaluationSpec(p).episode;
  e.duration = 1e9;
  EXPECT_EQ(validateEpisodeParams(e), "duration must be in (0, 10000] s");
  const auto model = parseCreatureModel(makeCreatureUrdf(1, "afc", p.unit), "afc");
  const AnnWingController ann(FlapUnitController(
      p.controller, std::vector<double>(FlapUnitController::weightCount(p.controller), 0.1)));
  EXPECT_THROW(runEpisode(model, ann, 0.02, e, EpisodeStart()), InputError);
  e.duration = 15.0;
  e.step_sizes = {0.001, 1e-6};  // 1.5e7 steps at the second
  EXPECT_EQ(validateEpisodeParams(e),
            "duration / step size = 1.5e+07 steps, over the limit of 1e+07 per episode");
  e.step_sizes = {1e-7};
  EXPECT_EQ(validateEpisodeParams(e), "step_sizes: step_size must be in [1e-6, 0.1] s");
  e.step_sizes = {};
  e.episodes = kMaxEpisodes + 1;
  EXPECT_EQ(validateEpisodeParams(e), "episodes must be in [1, 1000]");
}

std::string checkpointError(const std::string& text) {
  try {
    checkpointFromText(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The text of a 1-generation tinyRun checkpoint, with `from` replaced by `to` (once).
std::string tampered(const std::string& from, const std::string& to) {
  static const std::string text = [] {
    EvolveParams p = tinyRun();
    p.ga.generations = 1;
    std::string last;
    EvolveHooks hooks;
    hooks.on_checkpoint = [&](EvolveCheckpoint c) {
      c.args = {"--preset", "robust", "--seed", "7"};
      last = checkpointToText(c);
    };
    evolveFlapController(p, hooks);
    return last;
  }();
  std::string t = text;
  if (!from.empty()) t.replace(t.find(from), from.size(), to);
  return t;
}

// Issue 27, case 8 and smaller: a checkpoint's numbers are checked (NaN, inf, wrapped
// generations refused), its population must be the GA's (sorted, genes in range).
TEST(CheckpointLimits, TamperedNumbersAreRefusedByLine) {
  const std::string good = tampered("", "");
  EXPECT_EQ(checkpointError(good), "");
  const std::string fitness = good.substr(good.find("\n", good.find("population")) + 1, 10);
  EXPECT_EQ(checkpointError(tampered("generation 1", "generation 4294967298")),
            "checkpoint line 2: '4294967298' is not an integer in [0, 100000] (generation)");
  EXPECT_EQ(checkpointError(tampered("seed 7", "seed -1")),
            "checkpoint line 3: seed: '-1' is not an integer in [0, 2^64)");
  EXPECT_EQ(checkpointError(tampered(fitness, "nan")).find("checkpoint line 10: 'nan"), 0u);
  EXPECT_NE(checkpointError(tampered(fitness, "inf")).find("is not a finite number (fitness)"),
            std::string::npos);
  EXPECT_EQ(
      checkpointError(tampered("history 2\n0 ", "history 2\n0 nan ")).find("checkpoint line 15"),
      0u);
  EXPECT_NE(checkpointError(tampered("history 2", "history 3")).find("(generations)"),
            std::string::npos);
  EXPECT_NE(checkpointError(tampered("population 4", "population 4000000")).find("individuals"),
            std::string::npos);
  EXPECT_EQ(checkpointError(good + "junk\n"), "checkpoint line 17: unexpected 'junk' after 'end'");
}

// NSGA-II's individuals carry their objectives after their genes ("objectives K" on the
// population line): they read back to the bit, and a count of them is checked like the rest.
TEST(CheckpointLimits, ObjectivesReadBackToTheBitAndABadCountOrWordIsRefusedByLine) {
  EvolveCheckpoint c = checkpointFromText(tampered("", ""));
  for (Individual& ind : c.population) ind.objectives = {45.5 + ind.fitness, 1.0 / 3.0};
  const std::string text = checkpointToText(c);
  EXPECT_NE(text.find(" objectives 2\n"), std::string::npos) << text;
  const EvolveCheckpoint back = checkpointFromText(text);
  for (size_t i = 0; i < c.population.size(); ++i) {
    EXPECT_EQ(back.population[i].objectives, c.population[i].objectives) << i;
    EXPECT_EQ(back.population[i].genes, c.population[i].genes) << i;
  }
  auto swapped = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return checkpointError(t);
  };
  EXPECT_EQ(swapped(" objectives 2", " objectives 9"),
            "checkpoint line 9: '9' is not an integer in [1, 8] (objectives)");
  EXPECT_EQ(swapped(" objectives 2", " goals 2"),
            "checkpoint line 9: expected 'objectives' or the end of the line");
  EXPECT_NE(swapped(" objectives 2", " objectives 3").find("expected a number (objective)"),
            std::string::npos);
}

TEST(CheckpointLimits, APopulationTheGaCouldNotHaveIsRefusedOnResume) {
  EvolveParams p = tinyRun();
  p.ga.generations = 1;
  auto resumeError = [&](const std::string& text) {
    const EvolveCheckpoint c = checkpointFromText(text);
    EvolveHooks hooks;
    hooks.resume = &c;
    try {
      evolveFlapController(p, hooks);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(resumeError(tampered("", "")), "");
  EvolveCheckpoint c = checkpointFromText(tampered("", ""));
  std::swap(c.population[0], c.population[3]);  // unsorted: changed the result silently
  EXPECT_EQ(resumeError(checkpointToText(c)),
            "GA restore: the population is not sorted best first (individual 1)");
  c = checkpointFromText(tampered("", ""));
  c.population[2].genes[0] = 1e6;
  EXPECT_EQ(resumeError(checkpointToText(c)),
            "GA restore: individual 2 has a gene outside [gene_min, gene_max]");
  c = checkpointFromText(tampered("", ""));
  c.history.back().best += 1.0;
  EXPECT_EQ(resumeError(checkpointToText(c)),
            "GA restore: the history's last best is not the best individual's fitness");
}

// Issue 27, case 8: `--weights /elsewhere/x.yaml` added to a checkpoint's args made
// `evolve --resume DIR` write that file. Only the flags that define the run are read back.
TEST(CheckpointLimits, ArgsThatAreNotTheRunsFlagsAreRefused) {
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("flapsim_ckpt_" + std::to_string(::getpid())))
          .string();
  std::filesystem::create_directories(dir);
  for (const std::string arg : {"--weights", "--out", "--resume", "--farm-wait"}) {
    writeTextFile(dir + "/checkpoint.txt",
                  tampered("args 4\n", "args 6\n" + arg + "\n/elsewhere/x.yaml\n"));
    std::optional<EvolveCheckpoint> resume;
    try {
      resolveEvolveOptions({"--resume", dir}, 1, resume);
      ADD_FAILURE() << arg << " was read back";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), dir + "/checkpoint.txt: spec: '" + arg +
                                           "' is not a flag of the evolution's definition");
    }
    EXPECT_FALSE(resume.has_value());
  }
  writeTextFile(dir + "/checkpoint.txt", tampered("", ""));
  std::optional<EvolveCheckpoint> resume;
  const EvolveOptions o = resolveEvolveOptions({"--resume", dir, "--weights", "w.yaml"}, 1, resume);
  EXPECT_EQ(o.weights_path, "w.yaml");  // the command line's own flags still count
  EXPECT_EQ(o.out_dir, dir);
  ASSERT_TRUE(resume.has_value());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace flapsim
