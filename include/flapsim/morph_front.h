// The two objectives of a co-evolved hover creature (issue 44) and the Pareto front of a
// population (flapsim/pareto.h): the mechanical power per kg its motors give, and a loss
// that sums everything else its episodes penalise (altitude rms, tilt, sag, fall, flips).
// evolve --preset morph writes the front of its last population. ROS-free; no clock.
#pragma once

#include <string>
#include <vector>

#include "flapsim/episode_evaluator.h"
#include "flapsim/morph_evolution.h"

namespace flapsim {

/// A genome over the spec's episodes.
struct MorphScore {
  double power_per_kg = 0.0;  // W/kg: the motors' mean positive power over the episodes' mean
  /// m: the mean over the episodes of morphLoss (everything but the power): minimised.
  double loss = 0.0;
  double mass = 0.0;    // kg, the whole creature
  std::string refusal;  // not empty: the body was refused (no objectives)
};

/// The scores of `genomes` (each a morph genome) over the episodes of `spec` (kind kMorph), on
/// `threads` threads; the same bits on any count.
std::vector<MorphScore> morphScores(const std::vector<std::vector<double>>& genomes,
                                    const EvaluationSpec& spec, int threads);

/// Pareto ranks of scores by (power_per_kg, loss), both minimised; a refused body's rank is -1.
std::vector<int> morphRanks(const std::vector<MorphScore>& scores);

/// CSV of a population's scores, one row per genome in order: member, rank, W/kg, loss, the
/// creature's mass and the body's genes, and the refusal if any.
std::string morphFrontCsv(const std::vector<std::vector<double>>& genomes,
                          const std::vector<MorphScore>& scores, const std::vector<int>& ranks,
                          const MassBudget& budget);

/// gnuplot commands drawing `dir`/front.png from `dir`/front.csv: each built member's mean
/// loss (log scale) against its W/kg, the front's (rank 0) marked.
std::string morphFrontGnuplot(const std::string& dir);

}  // namespace flapsim
