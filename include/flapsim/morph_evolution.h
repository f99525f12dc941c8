// Co-evolution of the hover creature's body and controller (issue 44, evolve --preset morph):
// a genome is the hover controller's kHoverGeneCount gains followed by the body's
// kBodyGeneCount genes (flapsim/body_genome.h). An episode builds the body (buildBody under the
// default MassBudget) and flies it as the hover preset's episodes do; a body the budget or
// make_creature refuses scores the worst an episode can, so the run goes on with the others.
// ROS-free; no clock.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "flapsim/body_genome.h"
#include "flapsim/hover_evolution.h"

namespace flapsim {

constexpr int kMorphGeneCount = kHoverGeneCount + kBodyGeneCount;

/// Whether an evolution of `kind` flies the hover creature's controller (kHover, kMorph).
inline bool hoverKind(EvolveKind kind) {
  return kind == EvolveKind::kHover || kind == EvolveKind::kMorph;
}
/// The genes an individual of `kind` has among the hover kinds' (kHoverGeneCount or
/// kMorphGeneCount).
int hoverKindGeneCount(EvolveKind kind);

/// Empty if `genes` is a morph genome (the hover genes, then the body genes, each within
/// +-1), else a message naming the first culprit.
std::string checkMorphGenes(const std::vector<double>& genes);

/// The rad a morph's controller keeps its wings' stroke (amplitude + |offset|) inside the
/// body's stroke limit: its max_stroke is the limit less this (hover_1's 1.45 of 1.5).
constexpr double kMorphStrokeMargin = 0.05;

/// An individual of a morph genome: its body built (or refused) and its controller holding
/// `altitude`, the controller's max_stroke the body's stroke limit less kMorphStrokeMargin.
struct MorphIndividual {
  BodyBuild body;  // body.params: the body's HoverParams, built or not
  HoverControllerParams controller;
};
/// checkMorphGenes first (InputError naming the gene).
MorphIndividual morphFromGenes(const std::vector<double>& genes, double altitude,
                               const MassBudget& budget = MassBudget(),
                               const std::string& name = "morph");

/// A morph episode's fall term: the hover fitness caps its sag term at kHoverMaxTerm m of sag,
/// which every body that cannot lift itself reaches within 2 s, so a random population of
/// bodies scores alike. A morph episode also loses kMorphFallWeight per m the creature sank
/// below its start beyond that, up to a free fall's g T^2 / 2 over the episode's T, and a
/// flipped one (the flight ends at the flip) that whole free fall: a body that lifts part of
/// its weight scores above one that lifts less, and none gains by flipping early.
constexpr double kMorphFallWeight = 1.0;  // per m
double morphFallTerm(const HoverFlightResult& result, const EpisodeParams& params);
/// The largest |fitness| a morph episode can score: hoverFitnessBound + the free fall's term.
double morphFitnessBound(const EpisodeParams& params);

/// Everything a morph episode penalises but the power (m, >= 0): the hover fitness's other
/// terms and flip penalty, and morphFallTerm.
double morphLoss(const HoverFlightResult& result, const EpisodeParams& params);

/// Empty if `params` are valid (validateMassBudget, a finite power weight >= 0), else why not.
std::string validateMorphParams(const MorphParams& params);

/// One episode's flight of a morph genome: the hover preset's (runHoverEpisode) of the
/// individual's body (under `budget`) and controller; no flight if the body was refused.
struct MorphFlight {
  std::string refusal;  // not empty: the body was refused, and `result` is empty
  HoverFlightResult result;
};
MorphFlight flyMorphEpisode(const std::vector<double>& genes, const EpisodeParams& params,
                            const EpisodeStart& start, const MassBudget& budget);

/// One episode of a morph genome, scored: its flight (flyMorphEpisode under morph.budget)
/// scores -(morphLoss + hoverPowerTerm at morph.power_weight); a refused body scores
/// -morphFitnessBound(params).
double morphEpisodeFitness(const std::vector<double>& genes, const EpisodeParams& params,
                           const EpisodeStart& start, const MorphParams& morph);

/// The largest W/kg a morph episode answers as an objective: what a refused body answers (a
/// flight's stays far below: the motors' rated 6 W at most over a body of 8 g or more).
constexpr double kMaxMorphPower = 1e4;
/// One episode of a morph genome as NSGA-II's two objectives, both minimised: {the motors'
/// mean positive power per kg of the creature, morphLoss} of its flight (flyMorphEpisode
/// under morph.budget); a refused body {kMaxMorphPower, morphFitnessBound(params)}, dominated
/// by every flight.
std::vector<double> morphEpisodeObjectives(const std::vector<double>& genes,
                                           const EpisodeParams& params, const EpisodeStart& start,
                                           const MorphParams& morph);
/// The fitness of an episode's objectives at `power_weight`: -(loss + the power term capped at
/// kHoverMaxTerm), morphEpisodeFitness's value to the bit; a refused body's (power
/// kMaxMorphPower) -loss, i.e. -morphFitnessBound.
double morphObjectivesFitness(const std::vector<double>& objectives, double power_weight);

class EpisodeEvaluator;
/// evolve --preset morph --selection nsga2: NSGA-II (flapsim/pareto.h's Nsga2 with the GA's
/// population, generations, operators, seed and gene bounds, generation 0 seeded from
/// ga.initial_genes) over each genome's mean objectives over the spec's episodes
/// (morphEpisodeObjectives, through `evaluator`, two values per task). Each generation's
/// history figures are the population's fitness, morphObjectivesFitness of its mean objectives
/// at morph.power_weight (the GA's mean episode fitness, to rounding); the population kept in
/// NSGA-II's crowded order (front first), each individual with its objectives; best_weights
/// the fittest. Checkpoints and a resume (hooks) as the GA's: the same bits.
EvolveResult evolveMorphByNsga2(const EvolveParams& params, const EvaluationSpec& spec,
                                EpisodeEvaluator& evaluator, const EvolveHooks& hooks);

/// evolve --preset morph: the hover preset's episodes, GA and fitness (its power term weighs
/// the mechanical power per kg of the whole creature), on kMorphGeneCount genes.
EvolveParams morphPreset();

/// The body file of evolve --preset morph (OUT/body.yaml): the body genes' fields of `params`
/// as a YAML map, `header` lines first and the masses under `budget` and `metadata` after them
/// as comments.
std::string bodyToYaml(const HoverParams& params, const MassBudget& budget,
                       const std::string& header = "",
                       const std::map<std::string, std::string>& metadata = {});
/// The body genes of a body file's text: every gene's field given, each within its bounds.
/// Throws InputError naming `source` and the culprit (not a map, an unknown or missing key,
/// a value not a finite number or outside its gene's bounds).
std::vector<double> bodyGenesFromYaml(const std::string& text,
                                      const std::string& source = "<string>");
/// Reads (at most 64 KiB) and parses a body file.
std::vector<double> loadBodyGenes(const std::string& path);

}  // namespace flapsim
