// Fixtures of the co-evolution tests (test_morph_evolution, test_morph_nsga2): hover_1 as a
// morph genome, a budget its body closes, and two short episodes of the morph preset.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "flapsim/episode_evaluator.h"
#include "flapsim/evolve_args.h"
#include "flapsim/hover_gains.h"
#include "flapsim/morph_evolution.h"
#include "flapsim/text_file.h"

namespace flapsim {
namespace test {

// hover_1 as a genome: its evolved gains, and its body, whose stroke motors (stall 0.06 N m,
// no-load 300 rad/s) peak at 4.5 W; the genome's stall torque is theirs.
inline std::vector<double> flyingGenome() {
  std::vector<double> genes = hoverGenesFromParams(
      loadHoverGainsYaml(std::string(FLAPSIM_SOURCE_DIR) + "/config/hover_1_gains.yaml"));
  HoverParams body;
  body.max_power = 4.5;
  for (double g : bodyGenesFromParams(body)) genes.push_back(g);
  return genes;
}

// The body genes of flyingGenome().
inline std::vector<double> flyingBody() {
  const std::vector<double> genes = flyingGenome();
  return std::vector<double>(genes.begin() + kHoverGeneCount, genes.end());
}

// flyingBody() written as a body file in `dir` (its path).
inline std::string writeFlyingBodyFile(const std::string& dir) {
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/body.yaml";
  writeTextFile(path, bodyToYaml(bodyFromGenes(flyingBody(), MassBudget()), MassBudget()));
  return path;
}

// A budget hover_1's body closes: 2 x 4.5 W at 1000 W/kg (9 g, far lighter than any motor the
// default's source lists) and a 6 g payload in its 16 g body.
inline const std::vector<std::string> kLightMotors = {"--payload", "0.006",
                                                      "--motor-specific-power", "1000"};
inline MassBudget lightMotors() {
  MassBudget b;
  b.payload = 0.006;
  b.motor_specific_power = 1000.0;
  return b;
}

// Two short episodes of the morph preset, on that budget, with `more` flags.
inline EvaluationSpec shortSpec(const std::vector<std::string>& more = {}) {
  std::vector<std::string> args = {"--preset", "morph",    "--episodes", "2",      "--duration",
                                   "4",        "--settle", "2",          "--seed", "4"};
  args.insert(args.end(), kLightMotors.begin(), kLightMotors.end());
  args.insert(args.end(), more.begin(), more.end());
  return evaluationSpecFromArgs(args);
}

// What evolve's flags `args` are refused with (parseEvolveArgs), or "accepted".
inline std::string evolveRefusal(const std::vector<std::string>& args) {
  try {
    parseEvolveArgs(args, 1);
  } catch (const InputError& e) {
    return std::string(e.what());
  }
  return std::string("accepted");
}

}  // namespace test
}  // namespace flapsim
