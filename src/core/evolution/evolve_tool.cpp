#include "flapsim/evolve_tool.h"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "flapsim/ann.h"
#include "flapsim/controller_file.h"
#include "flapsim/hover_evolution.h"
#include "flapsim/hover_gains.h"
#include "flapsim/make_creature.h"
#include "flapsim/morph_evolution.h"
#include "flapsim/morph_front.h"

namespace flapsim {

namespace {

std::string formatDuration(double s) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  return buf;
}

// --init FILE of --preset hover: a gains file whose genes are within the range.
void seedFromGainsFile(EvolveOptions& o) {
  const std::vector<double> genes = hoverGenesFromParams(loadHoverGainsYaml(o.init_path));
  const std::string err = checkHoverGenes(genes);
  if (!err.empty()) {
    throw InputError("--init: " + o.init_path + ": " + err +
                     " (gains beyond the hover evolution's range)");
  }
  o.params.ga.initial_genes = genes;
}

// --preset morph: --init's gains (the hand-designed ones without it), then --init-body's body
// genes (the middle of every bound without it).
void seedMorph(EvolveOptions& o) {
  std::vector<double> genes(kMorphGeneCount, 0.0);
  if (!o.init_path.empty()) {
    seedFromGainsFile(o);
    std::copy(o.params.ga.initial_genes.begin(), o.params.ga.initial_genes.end(), genes.begin());
  }
  if (!o.init_body_path.empty()) {
    const std::vector<double> body = loadBodyGenes(o.init_body_path);
    std::copy(body.begin(), body.end(), genes.begin() + kHoverGeneCount);
  }
  o.params.ga.initial_genes = genes;
}

// A setting an --init file's weights were flown with: its key, the evolve flag that sets it
// (null: set by hand, never evolved), its value in the file and in the evolution, and whether
// it is a switch (1 on, 0 off: said so).
struct InitSetting {
  const char* key;
  const char* flag;
  double file, evolution;
  bool on_off = false;
};

// The settings a file's weights were flown with (the strokes', the inputs' scales, the phase
// lock, the chain pitch term, the terms set by hand), the file's `got` and the evolution's
// `want` on `pairs` units: a file flown otherwise would seed an evolution of a different
// controller, silently. An input's scale counts if the net has the input, the pitch term on a
// chain, its limits if it is on; a setting that does not count is 0 on both sides.
std::vector<InitSetting> initSettings(const FlapControllerParams& got,
                                      const FlapControllerParams& want, int pairs) {
  using Setting = InitSetting;
  const bool chain = pairs > 1;
  const bool pitch_term = chain && (got.pitch_gain > 0.0 || want.pitch_gain > 0.0);
  auto counted = [](bool counts, double value) { return counts ? value : 0.0; };
  return {
      Setting{"min_downstroke_rate", "--min-rate", got.min_downstroke_rate,
              want.min_downstroke_rate},
      Setting{"max_downstroke_rate", "--max-rate", got.max_downstroke_rate,
              want.max_downstroke_rate},
      Setting{"upstroke_rate", "--upstroke-rate", got.upstroke_rate, want.upstroke_rate},
      Setting{"max_upstroke_rate", "--max-upstroke-rate", got.max_upstroke_rate,
              want.max_upstroke_rate},
      Setting{"mixer_headroom", "--mixer-headroom", got.mixer_headroom, want.mixer_headroom},
      Setting{"amplitude", "--amplitude", got.amplitude, want.amplitude},
      Setting{"stroke_offset", "--stroke-offset", got.stroke_offset, want.stroke_offset},
      Setting{"control_period", "--control-period", got.control_period, want.control_period},
      Setting{"rate_scale", "--rate-scale", counted(want.rate_inputs, got.rate_scale),
              counted(want.rate_inputs, want.rate_scale)},
      Setting{"altitude_scale", "--altitude-scale",
              counted(want.altitude_input, got.altitude_scale),
              counted(want.altitude_input, want.altitude_scale)},
      Setting{"climb_scale", "--climb-scale", counted(want.climb_input, got.climb_scale),
              counted(want.climb_input, want.climb_scale)},
      Setting{"phase_lock", "--phase-lock", got.phase_lock ? 1.0 : 0.0, want.phase_lock ? 1.0 : 0.0,
              true},
      Setting{"pitch_gain", "--pitch-gain", counted(chain, got.pitch_gain),
              counted(chain, want.pitch_gain)},
      Setting{"pitch_limit", nullptr, counted(pitch_term, got.pitch_limit),
              counted(pitch_term, want.pitch_limit)},
      Setting{"pitch_max_downstroke_rate", nullptr,
              counted(pitch_term, got.pitch_max_downstroke_rate),
              counted(pitch_term, want.pitch_max_downstroke_rate)},
      Setting{"roll_reflex_bank", nullptr, got.roll_reflex_bank, want.roll_reflex_bank},
      Setting{"pitch_reflex_angle", nullptr, got.pitch_reflex_angle, want.pitch_reflex_angle},
      Setting{"attitude_filter_time", nullptr, got.attitude_filter_time, want.attitude_filter_time},
      Setting{"velocity_gain", nullptr, got.velocity_gain, want.velocity_gain}};
}

// --init FILE: the file's network must be the one evolved (same form, inputs, hidden layer
// and weight count); its weights seed generation 0.
void seedFromWeightsFile(EvolveOptions& o) {
  if (o.params.kind == EvolveKind::kMorph) return seedMorph(o);
  if (o.params.kind == EvolveKind::kHover) return seedFromGainsFile(o);
  const ControllerSpec init = loadControllerYaml(o.init_path);
  const FlapControllerParams& want = o.params.controller;
  const FlapControllerParams& got = init.params;
  if (got.network != want.network || flapInputNames(got) != flapInputNames(want) ||
      got.hidden != want.hidden || got.hidden_activation != want.hidden_activation ||
      init.weights.size() != static_cast<size_t>(FlapUnitController::weightCount(want))) {
    throw InputError("--init: " + o.init_path + " holds a " + toString(got.network) +
                     " network of " + std::to_string(init.weights.size()) +
                     " weights, not the evolution's " + toString(want.network) + " network of " +
                     std::to_string(FlapUnitController::weightCount(want)));
  }
  for (const InitSetting& s : initSettings(got, want, o.params.pairs)) {
    if (s.file != s.evolution) {
      auto value = [&s](double v) {
        std::ostringstream text;
        if (s.on_off) {
          text << (v != 0.0 ? "on" : "off");
        } else {
          text << v;
        }
        return text.str();
      };
      std::ostringstream m;
      m << "--init: " << o.init_path << ": its " << s.key << " is " << value(s.file)
        << ", the evolution's " << value(s.evolution);
      if (s.flag) {
        m << " (give " << s.flag << " " << value(s.file) << ")";
      } else {
        m << " (set by hand, not evolved: seed from a file without it)";
      }
      throw InputError(m.str());
    }
  }
  o.params.ga.initial_genes = init.weights;
  const std::string err = validateGaParams(o.params.ga);
  if (!err.empty()) throw InputError("--init: " + o.init_path + ": " + err + " (--gene-range)");
}

}  // namespace

EvolveOptions resolveEvolveOptions(const std::vector<std::string>& args, int threads,
                                   std::optional<EvolveCheckpoint>& resume) {
  EvolveOptions o = parseEvolveArgs(args, threads);
  if ((!o.init_path.empty() || !o.init_body_path.empty()) && !o.help) seedFromWeightsFile(o);
  if (o.resume_dir.empty() || o.help) return o;
  // The run's own flags, then the directory, then this command line's.
  EvolveCheckpoint c = readCheckpointFile(o.resume_dir + "/checkpoint.txt");
  std::vector<std::string> all = c.args;
  all.insert(all.end(), {"--out", o.resume_dir});
  all.insert(all.end(), args.begin(), args.end());
  o = parseEvolveArgs(all, threads, /*later_wins=*/true);
  resume = std::move(c);
  return o;
}

std::string evolveCommand(const EvolveOptions& o) {
  std::string command = "evolve";
  for (const auto& a : o.spec_args) command += " " + a;
  return command;  // --init and --init-body among them
}

double episodesPerSecond(const EvolveOptions& o, const GenerationStats& g, double dt) {
  return dt > 0.0 ? g.evaluations * o.params.episode.episodes / dt : 0.0;
}

double secondsLeft(const EvolveOptions& o, const GenerationStats& g, int first, double elapsed) {
  return elapsed / (g.generation + 1 - first) * (o.params.ga.generations - g.generation);
}

std::string evolveProgressLine(const EvolveOptions& o, const GenerationStats& g, int first,
                               double elapsed, double dt, int workers) {
  char line[256];
  std::snprintf(line, sizeof line,
                "generation %3d/%d  best %8.4f  mean %8.4f  %6.1f episodes/s  %d %s  elapsed %s  "
                "left ~%s\n",
                g.generation, o.params.ga.generations, g.best, g.mean, episodesPerSecond(o, g, dt),
                workers, o.farm ? "workers" : "threads", formatDuration(elapsed).c_str(),
                formatDuration(secondsLeft(o, g, first, elapsed)).c_str());
  return line;
}

namespace {

std::map<std::string, std::string> runMetadata(const EvolveOptions& o, const EvolveResult& result,
                                               double wall_s, const std::string& evaluated_on) {
  return {{"command", evolveCommand(o)},
          {"best_fitness", std::to_string(result.best_fitness)},
          {"first_best_fitness", std::to_string(result.history.front().best)},
          {"wall_time_s", std::to_string(wall_s)},
          {"threads", std::to_string(o.params.ga.threads)},
          {"evaluated_on", evaluated_on}};
}

std::string writtenLine(const EvolveOptions& o, const EvolveResult& result, double wall_s,
                        const std::string& files) {
  std::ostringstream line;
  line << std::fixed << std::setprecision(4) << "best fitness " << result.best_fitness
       << " (generation 0: " << result.history.front().best << "), wall time "
       << std::setprecision(1) << wall_s << " s; wrote " << o.weights_path << ", " << files << "\n";
  return line.str();
}

// The episodes the best's fitness is over, as the file's header says it: "32 episodes", or
// with --episode-sets all of them ("128 episodes (4 sets of 32, the last generation flown on
// every set)").
std::string episodesTerm(const EvolveParams& p) {
  std::ostringstream out;
  out << p.episode.episodes * p.episode_sets << " episodes";
  if (p.episode_sets > 1) {
    out << " (" << p.episode_sets << " sets of " << p.episode.episodes
        << ", the last generation flown on every set)";
  }
  return out.str();
}

// What ends a flap network's episode early, as the weights file's header says it.
std::string sealedEnds(const EpisodeParams& e) {
  if (e.flip_penalty <= 0.0) return "";
  std::ostringstream out;
  out << " (a flip" << (std::isfinite(e.crash_height) ? " or the root below " : "");
  if (std::isfinite(e.crash_height)) out << e.crash_height << " m";
  out << " ends one, less " << e.flip_penalty << " m)";
  return out.str();
}

// The episode's upright floor, as the fitness line says it ("" when off).
std::string uprightFloorTerm(const EpisodeParams& e) {
  if (!e.altitude_hold || e.upright_floor <= 0.0) return "";
  std::ostringstream out;
  out << ", each episode less " << e.upright_floor_weight
      << " m per unit its lowest up-component after " << e.settle_time << " s falls below "
      << e.upright_floor;
  return out.str();
}

// The episode's altitude rms ceiling, as the fitness line says it ("" when off).
std::string rmsCeilingTerm(const EpisodeParams& e) {
  if (!e.altitude_hold || e.altitude_rms_ceiling <= 0.0) return "";
  std::ostringstream out;
  out << ", each episode less " << e.altitude_rms_weight << " m per m its altitude rms after "
      << e.settle_time << " s exceeds " << e.altitude_rms_ceiling << " m";
  return out.str();
}

// --preset morph: the best's body file and URDF (its gains are written as hover's). The
// lines written, or why the body was refused.
std::string writeMorphBody(const EvolveOptions& o, const MorphIndividual& m,
                           const std::map<std::string, std::string>& metadata) {
  const MassBudget& budget = o.params.morph.budget;
  const std::string body = o.out_dir + "/body.yaml", urdf = o.out_dir + "/creature.urdf";
  writeTextFile(body,
                bodyToYaml(m.body.params, budget,
                           "Hover creature's body evolved with its controller (the "
                           "gains file of the run).\nReproduce: " +
                               evolveCommand(o) + " --out <dir>\nBuilt: creature.urdf beside it",
                           metadata));
  if (!m.body.model) return ", " + body + " (" + m.body.refusal + ": no URDF)";
  writeTextFile(urdf, m.body.urdf);
  return ", " + body + ", " + urdf;
}

// --preset morph: the Pareto front of the last population (its members flown again in
// process), OUT/front.csv, and each front member's gains and URDF (OUT/front_<k>_...).
std::string writeMorphFront(const EvolveOptions& o, const EvolveResult& result) {
  std::vector<std::vector<double>> genomes;
  for (const Individual& i : result.population) genomes.push_back(i.genes);
  const std::vector<MorphScore> scores =
      morphScores(genomes, evaluationSpec(o.params), o.params.ga.threads);
  const std::vector<int> ranks = morphRanks(scores);
  const std::string csv = o.out_dir + "/front.csv";
  writeTextFile(csv, morphFrontCsv(genomes, scores, ranks, o.params.morph.budget));
  int members = 0;
  for (size_t k = 0; k < genomes.size(); ++k) {
    if (ranks[k] != 0) continue;
    ++members;
    const MorphIndividual m = morphFromGenes(genomes[k], HoverControllerParams().altitude,
                                             o.params.morph.budget, "morph_" + std::to_string(k));
    const std::string stem = o.out_dir + "/front_" + std::to_string(k);
    char objectives[96];
    std::snprintf(objectives, sizeof objectives, " (%.2f W/kg, loss %.4f m)",
                  scores[k].power_per_kg, scores[k].loss);
    const std::string header = "Member " + std::to_string(k) + " of the front (front.csv)" +
                               objectives + " of the run\nReproduce: " + evolveCommand(o) +
                               " --out <dir>";
    writeTextFile(stem + "_gains.yaml", hoverGainsToYaml(m.controller, header));
    writeTextFile(stem + "_body.yaml", bodyToYaml(m.body.params, o.params.morph.budget, header));
    writeTextFile(stem + "_creature.urdf", m.body.urdf);
  }
  return ", " + csv + " (" + std::to_string(members) + " on the front: " + o.out_dir +
         "/front_<member>_gains.yaml, _body.yaml, _creature.urdf)";
}

// --preset hover and morph: the gains file and fitness.csv (morph: and its body).
std::string writeHoverOutputs(const EvolveOptions& o, const EvolveResult& result, double wall_s,
                              const std::string& evaluated_on) {
  const EpisodeParams& e = o.params.episode;
  const bool morph = o.params.kind == EvolveKind::kMorph;
  std::ostringstream header;
  header << "Hover controller gains (flapsim::HoverController) evolved "
         << (morph ? "with the creature's body (body.yaml, creature.urdf beside it) " : "")
         << (evaluated_on == "farm" ? "on the farm" : evaluated_on)
         << ".\nReproduce: " << evolveCommand(o) << " --out <dir>\n"
         << "Fitness = mean of -(altitude rms after " << e.settle_time << " s + "
         << (morph ? o.params.morph.power_weight : kHoverPowerWeight) << " x W/kg / 100 + "
         << (morph ? "the sink beyond 10 m of sag (a flip: a free fall) + " : "")
         << kHoverTiltWeight << " x (" << kHoverMinUpright << " - lowest up)+ + "
         << kHoverStartTiltWeight << " x (cos(start tilt + 10 deg) - lowest up from t = 0)+ + "
         << kHoverSagWeight << " x (sag below start and setpoint - " << kHoverMaxSag
         << " m)+, less " << e.flip_penalty << " after a flip) over " << episodesTerm(o.params)
         << " of " << e.duration << " s"
         << (e.first_start_level ? ", the first level in still air" : "") << ": "
         << result.best_fitness
         << "\nLoad it as hover_controller's private parameters (hover.launch gains:=FILE); "
         << "measure it with flight_check --hover " << (morph ? "--urdf <dir>/creature.urdf " : "")
         << "--gains FILE.";
  const auto metadata = runMetadata(o, result, wall_s, evaluated_on);
  std::optional<MorphIndividual> best;  // morph: the best's body and controller
  if (morph) {
    best = morphFromGenes(result.best_weights, HoverControllerParams().altitude,
                          o.params.morph.budget);
  }
  const HoverControllerParams gains =
      best ? best->controller : hoverParamsFromGenes(result.best_weights);
  writeTextFile(o.weights_path, hoverGainsToYaml(gains, header.str(), metadata));
  writeTextFile(o.out_dir + "/fitness.csv", fitnessCsv(result.history));
  const std::string body =
      best ? writeMorphBody(o, *best, metadata) + writeMorphFront(o, result) : "";
  return writtenLine(o, result, wall_s, o.out_dir + "/fitness.csv" + body);
}

}  // namespace

std::string writeEvolveOutputs(const EvolveOptions& o, const EvolveResult& result, double wall_s,
                               const std::string& evaluated_on) {
  if (hoverKind(o.params.kind)) {
    return writeHoverOutputs(o, result, wall_s, evaluated_on);
  }
  const EvolveParams& params = o.params;
  const ControllerSpec spec{params.controller, result.best_weights};
  std::ostringstream header;
  header << "Evolved flap-unit balance controller (flapsim, paper sec. IV.A).\n"
         << "Reproduce: " << evolveCommand(o) << " --out <dir>\n"
         << "Fitness = mean "
         << (params.episode.altitude_hold ? "of -|height - setpoint| - (1 - up-component) (m)"
                                          : "root-body height (m)")
         << " over " << episodesTerm(params) << " of " << params.episode.duration << " s"
         << sealedEnds(params.episode) << uprightFloorTerm(params.episode)
         << rmsCeilingTerm(params.episode) << ": " << result.best_fitness
         << "\nWeights: per neuron its input weights then its bias; hidden (tanh) neurons first,"
         << (params.controller.network == FlapNetwork::kMirror
                 ? " then the output (the right wing; the left is the net on mirrored inputs)."
                 : " then output 0 (right), output 1 (left).");
  writeTextFile(o.weights_path,
                controllerToYaml(spec, header.str(), runMetadata(o, result, wall_s, evaluated_on)));
  writeTextFile(o.out_dir + "/fitness.csv", fitnessCsv(result.history));

  // The best individual on the first evolution episode, for the rates plot (Fig. 7).
  EpisodeParams episode = params.episode;
  episode.seed = evolutionEpisodeSeed(params.ga.seed);
  const auto model = parseCreatureModel(makeCreatureUrdf(params.pairs, "afc", params.unit));
  const AnnWingController ann(FlapUnitController(spec.params, spec.weights));
  const EpisodeResult ep = runEpisode(model, ann, spec.params.control_period, episode,
                                      episodeStarts(episode, model.get()).front(), true);
  writeTextFile(o.out_dir + "/rates.csv", ratesCsv(ep.trace));
  return writtenLine(o, result, wall_s, o.out_dir + "/fitness.csv, " + o.out_dir + "/rates.csv");
}

bool plotEvolveOutputs(const std::string& out_dir, bool rates, bool front) {
  FILE* gp = popen("gnuplot", "w");
  if (gp == nullptr) return false;
  const std::string script =
      gnuplotScript(out_dir, 5.0, rates) + (front ? morphFrontGnuplot(out_dir) : "");
  const bool written = std::fputs(script.c_str(), gp) >= 0;
  return pclose(gp) == 0 && written;
}

}  // namespace flapsim
