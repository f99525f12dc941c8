#include "flapsim/morph_evolution.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "flapsim/text_file.h"
#include "io/yaml_keys.h"

namespace flapsim {

namespace {

constexpr std::size_t kMaxBodyFileBytes = 64u << 10;

}  // namespace

int hoverKindGeneCount(EvolveKind kind) {
  return kind == EvolveKind::kMorph ? kMorphGeneCount : kHoverGeneCount;
}

std::string checkMorphGenes(const std::vector<double>& genes) {
  if (genes.size() != static_cast<size_t>(kMorphGeneCount)) {
    return std::to_string(genes.size()) + " genes, a morph genome has " +
           std::to_string(kMorphGeneCount) + " (" + std::to_string(kHoverGeneCount) +
           " of the controller, " + std::to_string(kBodyGeneCount) + " of the body)";
  }
  const std::vector<double> controller(genes.begin(), genes.begin() + kHoverGeneCount);
  const std::string err = checkHoverGenes(controller);
  if (!err.empty()) return err;
  const std::vector<double> body(genes.begin() + kHoverGeneCount, genes.end());
  const std::string body_err = checkBodyGenes(body);
  return body_err.empty() ? "" : "body " + body_err;
}

MorphIndividual morphFromGenes(const std::vector<double>& genes, double altitude,
                               const MassBudget& budget, const std::string& name) {
  const std::string err = checkMorphGenes(genes);
  if (!err.empty()) throw InputError("morph genome: " + err);
  const std::vector<double> controller(genes.begin(), genes.begin() + kHoverGeneCount);
  const std::vector<double> body(genes.begin() + kHoverGeneCount, genes.end());
  MorphIndividual m;
  m.body = buildBody(body, budget, name);
  m.controller = hoverParamsFromGenes(controller, altitude);
  m.controller.max_stroke = m.body.params.stroke_limit - kMorphStrokeMargin;
  return m;
}

namespace {

double freeFall(const EpisodeParams& params) {
  return 0.5 * 9.81 * params.duration * params.duration;
}

}  // namespace

double morphFallTerm(const HoverFlightResult& r, const EpisodeParams& params) {
  const double fall = freeFall(params);
  const double sink = r.flipped ? fall : std::clamp(r.start_sag - kHoverMaxTerm, 0.0, fall);
  return kMorphFallWeight * sink;
}

double morphFitnessBound(const EpisodeParams& params) {
  return hoverFitnessBound(params) + kMorphFallWeight * freeFall(params);
}

double morphLoss(const HoverFlightResult& r, const EpisodeParams& params) {
  return -(hoverEpisodeFitness(r, params.flip_penalty) +
           hoverPowerTerm(r.specificPower(), kHoverPowerWeight)) +
         morphFallTerm(r, params);
}

std::string validateMorphParams(const MorphParams& params) {
  const std::string err = validateMassBudget(params.budget);
  if (!err.empty()) return err;
  if (!std::isfinite(params.power_weight) || params.power_weight < 0.0) {
    return "the power weight must be a number >= 0";
  }
  return "";
}

MorphFlight flyMorphEpisode(const std::vector<double>& genes, const EpisodeParams& params,
                            const EpisodeStart& start, const MassBudget& budget) {
  const MorphIndividual m = morphFromGenes(genes, HoverControllerParams().altitude, budget);
  MorphFlight f;
  if (!m.body.model) {
    f.refusal = m.body.refusal;
    return f;
  }
  f.result = runHoverEpisode(m.body.model, m.controller, params, start);
  return f;
}

double morphEpisodeFitness(const std::vector<double>& genes, const EpisodeParams& params,
                           const EpisodeStart& start, const MorphParams& morph) {
  const MorphFlight f = flyMorphEpisode(genes, params, start, morph.budget);
  if (!f.refusal.empty()) return -morphFitnessBound(params);
  return -(morphLoss(f.result, params) +
           hoverPowerTerm(f.result.specificPower(), morph.power_weight));
}

std::vector<double> morphEpisodeObjectives(const std::vector<double>& genes,
                                           const EpisodeParams& params, const EpisodeStart& start,
                                           const MorphParams& morph) {
  const MorphFlight f = flyMorphEpisode(genes, params, start, morph.budget);
  if (!f.refusal.empty()) return {kMaxMorphPower, morphFitnessBound(params)};
  return {f.result.specificPower(), morphLoss(f.result, params)};
}

double morphObjectivesFitness(const std::vector<double>& objectives, double power_weight) {
  if (objectives.size() != 2) throw InputError("morph objectives: need 2 (W/kg, loss)");
  const double power = objectives[0], loss = objectives[1];
  if (power >= kMaxMorphPower) return -loss;
  return -(loss + hoverPowerTerm(power, power_weight));
}

EvolveParams morphPreset() {
  EvolveParams p = hoverPreset();
  p.kind = EvolveKind::kMorph;
  return p;
}

std::string bodyToYaml(const HoverParams& params, const MassBudget& budget,
                       const std::string& header,
                       const std::map<std::string, std::string>& metadata) {
  std::ostringstream out;
  out << commentLines(header);
  for (const BodyGene& g : bodyGenes()) {
    out << g.name << ": " << shortestDecimal(params.*g.member) << "  # " << g.unit << ", " << g.min
        << " to " << g.max << "\n";
  }
  const BodyMass m = bodyMass(params, budget);
  std::ostringstream masses;
  masses << "masses: " << 1e3 * m.total << " g in all: body " << 1e3 * params.body_mass
         << " g (payload " << 1e3 * m.payload << ", motors " << 1e3 * m.motors << " at "
         << budget.motor_specific_power << " W/kg, ballast " << 1e3 * m.ballast << "), wings "
         << 1e3 * m.wings << " g; stall torque " << params.stall_torque << " N m";
  out << commentLines(masses.str());
  for (const auto& kv : metadata) out << commentLines(kv.first + ": " + kv.second);
  return out.str();
}

std::vector<double> bodyGenesFromYaml(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": not YAML: " + e.what());
  }
  if (!root.IsMap()) throw InputError(source + ": not a map of body genes");
  std::vector<std::string> known;
  for (const BodyGene& g : bodyGenes()) known.push_back(g.name);
  const std::string bad = badYamlKey(root, known);
  if (!bad.empty()) throw InputError(source + ": " + bad);
  HoverParams p;
  for (const BodyGene& g : bodyGenes()) {
    if (!root[g.name]) throw InputError(source + ": '" + g.name + "' is missing");
    double value = NAN;
    try {
      value = root[g.name].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(source + ": '" + g.name + "' is not a number");
    }
    if (!std::isfinite(value) || value < g.min || value > g.max) {
      throw InputError(source + ": '" + g.name + "' is " + shortestDecimal(value) + ", not in [" +
                       shortestDecimal(g.min) + ", " + shortestDecimal(g.max) + "] " + g.unit);
    }
    p.*g.member = value;
  }
  std::vector<double> genes = bodyGenesFromParams(p);
  for (double& gene : genes) gene = std::clamp(gene, -kBodyGeneRange, kBodyGeneRange);
  return genes;
}

std::vector<double> loadBodyGenes(const std::string& path) {
  return bodyGenesFromYaml(readTextFile(path, kMaxBodyFileBytes), path);
}

}  // namespace flapsim
