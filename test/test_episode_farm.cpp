// The episode task as a pure function, evaluators, checkpoints and resume, and the
// evolve flags: whatever evaluates the tasks and wherever a run is resumed, the
// evolution is the same bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"

namespace flapsim {
namespace {

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

// Evaluates the tasks one at a time in reverse order, on runners of its own, in chunks:
// as a farm would, answering in any order.
class ReverseEvaluator : public EpisodeEvaluator {
 public:
  explicit ReverseEvaluator(const EvaluationSpec& spec) : runner_(spec) {}
  std::vector<double> evaluate(const std::vector<EpisodeTask>& tasks) override {
    std::vector<double> out(tasks.size());
    for (size_t i = tasks.size(); i-- > 0;) out[i] = runner_.evaluate(tasks[i]);
    tasks_ += static_cast<int>(tasks.size());
    return out;
  }
  int workersUp() const override { return 1; }
  int tasks_ = 0;

 private:
  EpisodeRunner runner_;
};

TEST(EpisodeRunner, ATaskFliesTheSameAsRunEpisode) {
  const EvolveParams p = tinyRun();
  const EvaluationSpec spec = evaluationSpec(p);
  const EpisodeRunner runner(spec);
  std::vector<double> w(runner.weightCount());
  std::iota(w.begin(), w.end(), -3.0);
  const auto model = parseCreatureModel(makeCreatureUrdf(1, "afc", p.unit), "afc");
  const AnnWingController ann(FlapUnitController(p.controller, w));
  const auto starts = episodeStarts(spec.episode);
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

// Run 4 generations writing checkpoints; resume from the text of generation 1's and of
// generation 3's: both end as the uninterrupted run, bit for bit.
TEST(Resume, FromACheckpointEndsBitIdenticalToTheUninterruptedRun) {
  const EvolveParams p = tinyRun();
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

}  // namespace
}  // namespace flapsim
