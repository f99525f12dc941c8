// Episode evaluation as a pure function, and the dispatcher interface an
// evolution evaluates its (individual, episode) tasks through: in process on
// threads here, or on remote workers (the ROS farm in flapsim_ros). ROS-free;
// no clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "flapsim/evolve.h"

namespace flapsim {

/// Everything that is the same for every task of an evolution: what it evolves, the creature
/// (kFlap: pairs + unit parameters; kHover: the hover creature), the controller's settings and
/// the episodes (with the seed of their starts already set).
struct EvaluationSpec {
  EvolveKind kind = EvolveKind::kFlap;
  int pairs = 1;
  FlapUnitParams unit;
  FlapControllerParams controller;
  EpisodeParams episode;
  MorphParams morph;  // kMorph: the bodies' budget and the power weight
};

/// One (individual, episode) task: network weights (kHover: the gain genes) and an index into
/// episodeStarts(spec.episode).
struct EpisodeTask {
  std::vector<double> weights;
  int episode = 0;
};

/// A task that does not fit its spec (wrong weight count, a non-finite
/// weight, an episode index out of range).
class TaskError : public InputError {
 public:
  using InputError::InputError;
};

/// Limits of one farm call (doc/reliability.md): a worker refuses a call beyond them, and the
/// farm splits its batches to fit. The work of a call is its tasks times episodeWork: world
/// steps times wing pairs, about 8 us each on one core of the reference machine, so a call
/// holds a worker's thread for at most about 16 s there.
constexpr int kMaxTasksPerCall = 1024;
constexpr double kMaxCallWork = 2e6;

/// Empty if `spec`'s episodes, controller and (by its kind) hover episodes and morph params
/// are valid, else the first message naming what is not (evaluationSpec and EpisodeRunner).
std::string validateEvaluationSpec(const EvaluationSpec& spec);

/// The work of one episode of `spec`: pairs times the steps of the episode at its smallest
/// step size.
double episodeWork(const EvaluationSpec& spec);

/// The largest |fitness| an episode of `spec` can score: the start height, plus the
/// distance at the watchdog's speed limit over the episode, plus the flip penalty. A value
/// beyond it (or not finite) is not an episode's.
double fitnessBound(const EvaluationSpec& spec);

/// The values an episode of `spec` answers: 1, its fitness; 2 for a morph spec selected by
/// NSGA-II (MorphParams::nsga2), its motors' W/kg and its loss (morphEpisodeObjectives).
int taskValueCount(const EvaluationSpec& spec);

/// The largest magnitude each of an episode's values can have (fitnessBound for a fitness;
/// kMaxMorphPower and morphFitnessBound for the W/kg and loss); a value beyond it (or not
/// finite) is not an episode's.
std::vector<double> taskValueBounds(const EvaluationSpec& spec);

/// Evaluates tasks of one spec: the creature model and episode starts are
/// built once. evaluate() is const and thread-safe; its result depends on the
/// spec and the task alone (bit for bit, whatever the thread or process).
class EpisodeRunner {
 public:
  /// Throws InputError for an invalid spec.
  explicit EpisodeRunner(const EvaluationSpec& spec);
  /// The episode's fitness. Throws TaskError for a task that does not fit.
  double evaluate(const EpisodeTask& task) const;
  /// The episode's taskValueCount(spec()) values (its fitness alone, or a morph's objectives).
  /// Throws TaskError for a task that does not fit.
  std::vector<double> values(const EpisodeTask& task) const;
  /// Empty if `task` fits the spec, else a message naming what is wrong.
  std::string check(const EpisodeTask& task) const;
  int weightCount() const { return weight_count_; }
  int episodeCount() const { return static_cast<int>(starts_.size()); }
  const EvaluationSpec& spec() const { return spec_; }
  /// An estimate of the memory it holds (bytes): model, starts, spec.
  std::size_t bytes() const { return bytes_; }

 private:
  EvaluationSpec spec_;
  CreatureModelPtr model_;
  std::vector<EpisodeStart> starts_;
  int weight_count_ = 0;
  std::size_t bytes_ = 0;
};

/// Largest memory a RunnerCache holds (bytes, by EpisodeRunner::bytes() and the specs' text).
constexpr std::size_t kMaxRunnerCacheBytes = 16u << 20;

/// The runners of the specs a worker saw recently: at most `max_bytes` of them, the least
/// recently used given up first. Thread-safe.
class RunnerCache {
 public:
  explicit RunnerCache(std::size_t max_bytes = kMaxRunnerCacheBytes) : max_bytes_(max_bytes) {}
  /// The runner of evaluationSpecFromArgs(spec_args) (flapsim/evolve_args.h). Throws
  /// InputError for a bad spec.
  std::shared_ptr<const EpisodeRunner> get(const std::vector<std::string>& spec_args);
  std::size_t bytes() const;
  std::size_t size() const;

 private:
  struct Entry {
    std::vector<std::string> spec;
    std::shared_ptr<const EpisodeRunner> runner;
    std::size_t bytes = 0;
  };
  std::size_t max_bytes_;
  mutable std::mutex mutex_;
  std::list<Entry> entries_;  // most recently used first
  std::size_t bytes_ = 0;
};

/// Evaluates a batch of tasks and returns taskValueCount(spec) values per task (one fitness,
/// or a morph's two objectives), in task order. Implementations may run tasks anywhere and in
/// any order; the values must be those of EpisodeRunner::values.
class EpisodeEvaluator {
 public:
  virtual ~EpisodeEvaluator() = default;
  virtual std::vector<double> evaluate(const std::vector<EpisodeTask>& tasks) = 0;
  /// Workers (threads or remote workers) available at the last batch.
  virtual int workersUp() const = 0;
};

/// Each genome's mean over the `episodes` episodes from index `first` of each of its `values`
/// task values (one task per (genome, episode), the genome's first, evaluated by `evaluator`
/// in one batch, summed in episode order and divided by `episodes`). Throws
/// std::runtime_error if the evaluator returns another count than `values` per task.
std::vector<std::vector<double>> meanEpisodeValues(EpisodeEvaluator& evaluator, int episodes,
                                                   size_t values,
                                                   const std::vector<std::vector<double>>& genomes,
                                                   int first = 0);

/// In this process, on `threads` threads.
class InProcessEvaluator : public EpisodeEvaluator {
 public:
  InProcessEvaluator(const EvaluationSpec& spec, int threads);
  std::vector<double> evaluate(const std::vector<EpisodeTask>& tasks) override;
  int workersUp() const override { return threads_; }

 private:
  EpisodeRunner runner_;
  int threads_;
};

}  // namespace flapsim
