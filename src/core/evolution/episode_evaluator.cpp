#include "flapsim/episode_evaluator.h"

#include <cmath>

#include "flapsim/ga.h"

namespace flapsim {

EpisodeRunner::EpisodeRunner(const EvaluationSpec& spec) : spec_(spec) {
  std::string err = validateEpisodeParams(spec.episode);
  if (err.empty()) err = validateFlapControllerParams(spec.controller);
  if (err.empty() && spec.pairs < 1) err = "pairs must be >= 1";
  if (!err.empty()) throw InputError("evaluation spec: " + err);
  model_ = parseCreatureModel(makeCreatureUrdf(spec.pairs, "afc", spec.unit), "make_creature");
  starts_ = episodeStarts(spec.episode, model_.get());
  weight_count_ = FlapUnitController::weightCount(spec.controller);
}

std::string EpisodeRunner::check(const EpisodeTask& task) const {
  if (static_cast<int>(task.weights.size()) != weight_count_) {
    return std::to_string(task.weights.size()) + " weights, the controller has " +
           std::to_string(weight_count_);
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
  const AnnWingController ann(FlapUnitController(spec_.controller, task.weights));
  return runEpisode(model_, ann, spec_.controller.control_period, spec_.episode,
                    starts_[task.episode])
      .fitness;
}

InProcessEvaluator::InProcessEvaluator(const EvaluationSpec& spec, int threads)
    : runner_(spec), threads_(std::max(1, threads)) {}

std::vector<double> InProcessEvaluator::evaluate(const std::vector<EpisodeTask>& tasks) {
  return parallelMap(static_cast<int>(tasks.size()), threads_,
                     [&](int i) { return runner_.evaluate(tasks[i]); });
}

}  // namespace flapsim
