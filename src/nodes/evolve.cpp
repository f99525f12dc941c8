// evolve: runs the GA on the flap-unit network headless and writes the best
// weights (YAML), fitness per generation (CSV), the best individual's wing
// rates over an episode (CSV) and two PNG plots (gnuplot). See --help.
#include "flapsim/evolve.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include "flapsim/make_creature.h"

namespace {

const char* kUsage =
    "usage: evolve [options]\n"
    "  --preset NAME      robust (default) or paper; the options below change it\n"
    "                     (defaults shown are the paper preset's)\n"
    "  --pairs N          wing pairs of the creature (1)\n"
    "  --generations G    generations after the initial one (200)\n"
    "  --population P     individuals (10)\n"
    "  --seed S           GA and start-attitude seed (1)\n"
    "  --threads T        parallel episodes (hardware threads); results do not depend on it\n"
    "  --duration D       episode length, s (30)\n"
    "  --episodes E       episodes per evaluation, start roll alternating +/- (8)\n"
    "  --min-rate R       lowest downstroke rate, rad/s (20)\n"
    "  --max-rate R       highest downstroke rate, rad/s (60)\n"
    "  --upstroke-rate R  upstroke rate, rad/s (10)\n"
    "  --amplitude A      stroke amplitude, rad (1.2)\n"
    "  --control-period P network update period, s (0.02)\n"
    "  --roll LO HI       start roll range, rad (0.035 0.087; robust 0 0.35)\n"
    "  --pitch P          start pitch range +-P, rad (0.035; robust 0.35)\n"
    "  --link-stiffness K spring on the joints between units, N m/rad (0.5)\n"
    "  --start-rate W     start angular velocity, up to W rad/s per axis (0; robust 1)\n"
    "  --gust G           a horizontal wind step of up to G m/s (0; robust 1)\n"
    "  --input-noise N    attitude-sensor noise, rad (0; robust 0.02)\n"
    "  --step-sizes LIST  step sizes drawn per episode, e.g. 0.001,0.0005 (robust)\n"
    "  --flip-penalty P   a flip ends the episode, less P m (0: off; robust 20)\n"
    "  --phase-lock B     on/off: upstroke follows downstroke, fixed period (robust on)\n"
    "  --gene-range G     initial range and bound of every weight, +-G (10)\n"
    "  --air-model M      air model of the episodes: pressure or quasi_steady (pressure)\n"
    "  --out DIR          output directory (evolve_out)\n"
    "  --weights FILE     weights YAML (DIR/weights.yaml)\n"
    "  --no-plot          do not run gnuplot\n";

std::string formatDuration(double s) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  flapsim::EvolveParams params = flapsim::robustPreset();
  std::string preset = "robust";
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--preset") preset = argv[i + 1];
  }
  if (preset == "paper") {
    params = flapsim::paperPreset();
  } else if (preset != "robust") {
    std::cerr << "evolve: unknown preset '" << preset << "' (robust or paper)\n";
    return 2;
  }
  params.ga.threads = std::max(1u, std::thread::hardware_concurrency());
  std::string out_dir = "evolve_out", weights_path;
  bool plot = true;
  std::ostringstream command;
  command << "evolve --preset " << preset;
  for (int i = 1; i < argc; ++i) {  // the reproducing command: all but where to write, threads
    const std::string a = argv[i];
    if ((a == "--threads" || a == "--out" || a == "--weights" || a == "--preset") && i + 1 < argc)
      ++i;
    else if (a != "--no-plot" && a.find(":=") == std::string::npos)
      command << " " << a;
  }
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a.find(":=") != std::string::npos) continue;  // roslaunch's __name:=, __log:=
      if (a == "--help" || a == "-h") {
        std::cout << kUsage;
        return 0;
      }
      if (a == "--no-plot") {
        plot = false;
        continue;
      }
      if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
      const std::string v = argv[++i];
      if (a == "--preset")
        continue;  // applied first
      else if (a == "--pairs")
        params.pairs = std::stoi(v);
      else if (a == "--generations")
        params.ga.generations = std::stoi(v);
      else if (a == "--population")
        params.ga.population = std::stoi(v);
      else if (a == "--seed")
        params.ga.seed = std::stoull(v);
      else if (a == "--threads")
        params.ga.threads = std::stoi(v);
      else if (a == "--duration")
        params.episode.duration = std::stod(v);
      else if (a == "--episodes")
        params.episode.episodes = std::stoi(v);
      else if (a == "--min-rate")
        params.controller.min_downstroke_rate = std::stod(v);
      else if (a == "--max-rate")
        params.controller.max_downstroke_rate = std::stod(v);
      else if (a == "--upstroke-rate")
        params.controller.upstroke_rate = std::stod(v);
      else if (a == "--amplitude")
        params.controller.amplitude = std::stod(v);
      else if (a == "--roll" && i + 1 < argc) {
        params.episode.min_roll = std::stod(v);
        params.episode.max_roll = std::stod(argv[++i]);
      } else if (a == "--link-stiffness")
        params.unit.link_stiffness = std::stod(v);
      else if (a == "--pitch")
        params.episode.max_pitch = std::stod(v);
      else if (a == "--start-rate")
        params.episode.max_start_rate = std::stod(v);
      else if (a == "--gust")
        params.episode.max_gust = std::stod(v);
      else if (a == "--input-noise")
        params.episode.input_noise = std::stod(v);
      else if (a == "--flip-penalty")
        params.episode.flip_penalty = std::stod(v);
      else if (a == "--phase-lock") {
        if (v != "on" && v != "off") throw std::invalid_argument("--phase-lock takes on or off");
        params.controller.phase_lock = v == "on";
      } else if (a == "--step-sizes") {
        params.episode.step_sizes.clear();
        std::istringstream list(v);
        for (std::string item; std::getline(list, item, ',');) {
          params.episode.step_sizes.push_back(std::stod(item));
        }
      } else if (a == "--control-period")
        params.controller.control_period = std::stod(v);
      else if (a == "--gene-range") {
        params.ga.gene_max = std::stod(v);
        params.ga.gene_min = -params.ga.gene_max;
      } else if (a == "--air-model")
        params.episode.world.air.model = v;
      else if (a == "--out")
        out_dir = v;
      else if (a == "--weights")
        weights_path = v;
      else
        throw std::invalid_argument("unknown option " + a);
    }
  } catch (const std::exception& e) {
    std::cerr << "evolve: " << e.what() << "\n" << kUsage;
    return 2;
  }
  if (weights_path.empty()) weights_path = out_dir + "/weights.yaml";

  try {
    std::filesystem::create_directories(out_dir);
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const flapsim::EvolveResult result =
        flapsim::evolveFlapController(params, [&](const flapsim::GenerationStats& g) {
          const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
          const double left = elapsed / (g.generation + 1) * (params.ga.generations - g.generation);
          std::printf("generation %3d/%d  best %8.4f  mean %8.4f  elapsed %s  left ~%s\n",
                      g.generation, params.ga.generations, g.best, g.mean,
                      formatDuration(elapsed).c_str(), formatDuration(left).c_str());
          std::fflush(stdout);
        });
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();

    flapsim::ControllerSpec spec{params.controller, result.best_weights};
    std::ostringstream header;
    header << "Evolved flap-unit balance controller (flapsim, paper sec. IV.A).\n"
           << "Reproduce: " << command.str() << " --out <dir>\n"
           << "Fitness = mean root-body height (m) over " << params.episode.episodes
           << " episodes of " << params.episode.duration << " s: " << result.best_fitness
           << "\nWeights: per neuron its input weights then its bias; hidden (tanh) neurons first,"
           << " then output 0 (right), output 1 (left).";
    std::map<std::string, std::string> meta = {
        {"command", command.str()},
        {"best_fitness", std::to_string(result.best_fitness)},
        {"first_best_fitness", std::to_string(result.history.front().best)},
        {"wall_time_s", std::to_string(wall)},
        {"threads", std::to_string(params.ga.threads)}};
    flapsim::writeTextFile(weights_path, flapsim::controllerToYaml(spec, header.str(), meta));
    flapsim::writeTextFile(out_dir + "/fitness.csv", flapsim::fitnessCsv(result.history));

    // The best individual on the first evolution episode, for the rates plot (Fig. 7).
    flapsim::EpisodeParams episode = params.episode;
    episode.seed = flapsim::evolutionEpisodeSeed(params.ga.seed);
    const auto model =
        flapsim::parseCreatureModel(flapsim::makeCreatureUrdf(params.pairs, "afc", params.unit));
    const flapsim::AnnWingController ann(flapsim::FlapUnitController(spec.params, spec.weights));
    const flapsim::EpisodeResult ep =
        flapsim::runEpisode(model, ann, spec.params.control_period, episode,
                            flapsim::episodeStarts(episode).front(), true);
    flapsim::writeTextFile(out_dir + "/rates.csv", flapsim::ratesCsv(ep.trace));
    std::printf(
        "best fitness %.4f (generation 0: %.4f), wall time %.1f s; wrote %s, %s/fitness.csv,"
        " %s/rates.csv\n",
        result.best_fitness, result.history.front().best, wall, weights_path.c_str(),
        out_dir.c_str(), out_dir.c_str());

    if (plot) {
      FILE* gp = popen("gnuplot", "w");
      const std::string script = flapsim::gnuplotScript(out_dir);
      if (gp == nullptr || std::fputs(script.c_str(), gp) < 0 || pclose(gp) != 0) {
        std::fprintf(stderr, "evolve: gnuplot failed (apt package gnuplot-nox); no plots\n");
        return 1;
      }
      std::printf("wrote %s/fitness.png, %s/rates.png\n", out_dir.c_str(), out_dir.c_str());
    }
  } catch (const std::exception& e) {
    std::cerr << "evolve: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
