#include "flapsim/episode_evaluator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "flapsim/evolve_args.h"
#include "flapsim/ga.h"
#include "flapsim/hover_evolution.h"
#include "flapsim/morph_evolution.h"

namespace flapsim {

double episodeWork(const EvaluationSpec& spec) {
  double smallest = spec.episode.world.step_size;
  for (size_t k = 0; k < spec.episode.step_sizes.size(); ++k) {
    smallest = k == 0 ? spec.episode.step_sizes[k] : std::min(smallest, spec.episode.step_sizes[k]);
  }
  const int pairs = hoverKind(spec.kind) ? 1 : spec.pairs;
  return pairs * std::ceil(spec.episode.duration / smallest);
}

double fitnessBound(const EvaluationSpec& spec) {
  const EpisodeParams& e = spec.episode;
  if (spec.kind == EvolveKind::kMorph) return morphFitnessBound(e);
  if (spec.kind == EvolveKind::kHover) return hoverFitnessBound(e);
  return std::abs(e.start_height) + e.world.max_speed * e.duration + e.flip_penalty;
}

int taskValueCount(const EvaluationSpec& spec) {
  return spec.kind == EvolveKind::kMorph && spec.morph.nsga2 ? 2 : 1;
}

std::vector<double> taskValueBounds(const EvaluationSpec& spec) {
  if (taskValueCount(spec) == 2) return {kMaxMorphPower, morphFitnessBound(spec.episode)};
  return {fitnessBound(spec)};
}

std::string validateEvaluationSpec(const EvaluationSpec& spec) {
  std::string err = validateEpisodeParams(spec.episode);
  if (err.empty()) err = validateFlapControllerParams(spec.controller);
  if (err.empty() && hoverKind(spec.kind)) err = validateHoverEpisodes(spec.episode);
  if (err.empty() && spec.kind == EvolveKind::kMorph) err = validateMorphParams(spec.morph);
  return err;
}

EpisodeRunner::EpisodeRunner(const EvaluationSpec& spec) : spec_(spec) {
  std::string err;
  if (spec.pairs < 1 || spec.pairs > kMaxEvolvePairs) {
    err = "pairs must be in [1, " + std::to_string(kMaxEvolvePairs) + "]";
  }
  if (err.empty()) err = validateEvaluationSpec(spec);
  if (!err.empty()) throw InputError("evaluation spec: " + err);
  // A morph's bodies are its genomes': each episode builds its own (its starts are drawn on
  // hover_1, whose link names, all the draws read, every body shares).
  const bool hover = hoverKind(spec.kind);
  model_ =
      hover ? parseCreatureModel(makeHoverUrdf("hover"), "make_creature --layout hover")
            : parseCreatureModel(makeCreatureUrdf(spec.pairs, "afc", spec.unit), "make_creature");
  starts_ = episodeStarts(spec.episode, model_.get());
  weight_count_ =
      hover ? hoverKindGeneCount(spec.kind) : FlapUnitController::weightCount(spec.controller);
  // An estimate, for caches: the model's records with their names and boxes, the starts.
  bytes_ = sizeof(*this) + model_->links.size() * (sizeof(LinkModel) + 512) +
           model_->joints.size() * (sizeof(JointModel) + 256) +
           starts_.size() * sizeof(EpisodeStart) + spec.episode.step_sizes.size() * sizeof(double);
}

std::string EpisodeRunner::check(const EpisodeTask& task) const {
  if (static_cast<int>(task.weights.size()) != weight_count_) {
    return std::to_string(task.weights.size()) + " weights, the controller has " +
           std::to_string(weight_count_);
  }
  if (hoverKind(spec_.kind)) {
    const std::string err = spec_.kind == EvolveKind::kMorph ? checkMorphGenes(task.weights)
                                                             : checkHoverGenes(task.weights);
    if (!err.empty()) return err;
  }
  for (size_t i = 0; i < task.weights.size(); ++i) {
    if (!std::isfinite(task.weights[i])) return "weight " + std::to_string(i) + " is not finite";
  }
  if (task.episode < 0 || task.episode >= episodeCount()) {
    return "episode " + std::to_string(task.episode) + " is not in [0, " +
           std::to_string(episodeCount()) + ")";
  }
  return "";
}

double EpisodeRunner::evaluate(const EpisodeTask& task) const {
  const std::string err = check(task);
  if (!err.empty()) throw TaskError("task: " + err);
  if (spec_.kind == EvolveKind::kMorph) {
    return morphEpisodeFitness(task.weights, spec_.episode, starts_[task.episode], spec_.morph);
  }
  if (spec_.kind == EvolveKind::kHover) {
    const HoverFlightResult r = runHoverEpisode(model_, hoverParamsFromGenes(task.weights),
                                                spec_.episode, starts_[task.episode]);
    return hoverEpisodeFitness(r, spec_.episode.flip_penalty);
  }
  const AnnWingController ann(FlapUnitController(spec_.controller, task.weights));
  return runEpisode(model_, ann, spec_.controller.control_period, spec_.episode,
                    starts_[task.episode])
      .fitness;
}

std::vector<double> EpisodeRunner::values(const EpisodeTask& task) const {
  if (taskValueCount(spec_) == 1) return {evaluate(task)};
  const std::string err = check(task);
  if (!err.empty()) throw TaskError("task: " + err);
  return morphEpisodeObjectives(task.weights, spec_.episode, starts_[task.episode], spec_.morph);
}

std::shared_ptr<const EpisodeRunner> RunnerCache::get(const std::vector<std::string>& spec_args) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
      if (it->spec != spec_args) continue;
      entries_.splice(entries_.begin(), entries_, it);
      return it->runner;
    }
  }
  // Built outside the lock (parses a URDF); two threads may build the same one.
  auto runner = std::make_shared<const EpisodeRunner>(evaluationSpecFromArgs(spec_args));
  std::size_t bytes = runner->bytes();
  for (const auto& a : spec_args) bytes += a.size() + sizeof(std::string);
  std::lock_guard<std::mutex> lock(mutex_);
  entries_.push_front(Entry{spec_args, runner, bytes});
  bytes_ += bytes;
  while (bytes_ > max_bytes_ && !entries_.empty()) {
    bytes_ -= entries_.back().bytes;
    entries_.pop_back();  // the runner lives on in the calls that hold it
  }
  return runner;
}

std::size_t RunnerCache::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bytes_;
}

std::size_t RunnerCache::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_.size();
}

std::vector<std::vector<double>> meanEpisodeValues(EpisodeEvaluator& evaluator, int episodes,
                                                   size_t values,
                                                   const std::vector<std::vector<double>>& genomes,
                                                   int first) {
  std::vector<EpisodeTask> tasks;
  tasks.reserve(genomes.size() * episodes);
  for (const auto& g : genomes) {
    for (int k = 0; k < episodes; ++k) tasks.push_back(EpisodeTask{g, first + k});
  }
  const std::vector<double> v = evaluator.evaluate(tasks);
  if (v.size() != values * tasks.size()) {
    throw std::runtime_error("evolve: the evaluator returned " + std::to_string(v.size()) +
                             " values for " + std::to_string(tasks.size()) + " tasks" +
                             (values == 1 ? "" : " of " + std::to_string(values) + " values"));
  }
  std::vector<std::vector<double>> means(genomes.size(), std::vector<double>(values, 0.0));
  for (size_t i = 0; i < genomes.size(); ++i) {
    for (int k = 0; k < episodes; ++k) {
      for (size_t m = 0; m < values; ++m) means[i][m] += v[values * (i * episodes + k) + m];
    }
    for (double& x : means[i]) x /= episodes;
  }
  return means;
}

InProcessEvaluator::InProcessEvaluator(const EvaluationSpec& spec, int threads)
    : runner_(spec), threads_(std::max(1, threads)) {}

std::vector<double> InProcessEvaluator::evaluate(const std::vector<EpisodeTask>& tasks) {
  const size_t k = static_cast<size_t>(taskValueCount(runner_.spec()));
  std::vector<double> out(tasks.size() * k);
  parallelMap(static_cast<int>(tasks.size()), threads_, [&](int i) {
    const std::vector<double> v = runner_.values(tasks[i]);  // each task its own slots
    std::copy(v.begin(), v.end(), out.begin() + static_cast<long>(i * k));
    return 0.0;
  });
  return out;
}

}  // namespace flapsim
