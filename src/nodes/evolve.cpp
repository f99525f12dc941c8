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
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "flapsim/evolve_args.h"
#include "flapsim/make_creature.h"
#include "flapsim_ros/episode_farm.h"

namespace {

std::string formatDuration(double s) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%dm%02ds", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::string> args(argv + 1, argv + argc);
  flapsim::EvolveOptions opt;
  std::optional<flapsim::EvolveCheckpoint> resume;
  try {
    opt = flapsim::parseEvolveArgs(args, threads);
    if (!opt.resume_dir.empty()) {
      // The run's own flags, then the directory, then this command line's.
      resume =
          flapsim::checkpointFromText(flapsim::readTextFile(opt.resume_dir + "/checkpoint.txt"));
      std::vector<std::string> all = resume->args;
      all.insert(all.end(), {"--out", opt.resume_dir});
      all.insert(all.end(), args.begin(), args.end());
      opt = flapsim::parseEvolveArgs(all, threads);
    }
  } catch (const std::exception& e) {
    std::cerr << "evolve: " << e.what() << "\n" << flapsim::evolveUsage();
    return 2;
  }
  if (opt.help) {
    std::cout << flapsim::evolveUsage();
    return 0;
  }
  const flapsim::EvolveParams& params = opt.params;
  const std::string& out_dir = opt.out_dir;
  const std::string& weights_path = opt.weights_path;
  std::ostringstream command;  // the reproducing command: the flags that define the run
  command << "evolve";
  for (const auto& a : opt.spec_args) command << " " << a;
  std::unique_ptr<ros::NodeHandle> nh;
  std::unique_ptr<flapsim_ros::FarmEvaluator> farm;
  std::unique_ptr<flapsim_ros::ProgressPublisher> progress;
  if (opt.farm) {
    ros::init(argc, argv, "evolve", ros::init_options::AnonymousName);
    nh = std::make_unique<ros::NodeHandle>();
    flapsim_ros::FarmParams fp;
    fp.timeout = opt.farm_timeout;
    fp.wait = opt.farm_wait;
    fp.inflight = opt.farm_inflight;
    fp.batch = opt.farm_batch;
    farm = std::make_unique<flapsim_ros::FarmEvaluator>(
        *nh, opt.spec_args, flapsim::FlapUnitController::weightCount(params.controller), fp);
    progress = std::make_unique<flapsim_ros::ProgressPublisher>(*nh, fp.ns);
  }

  try {
    std::filesystem::create_directories(out_dir);
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    auto last = start;
    const int first = resume ? resume->generation + 1 : 0;
    flapsim::EvolveHooks hooks;
    hooks.evaluator = farm.get();
    hooks.resume = resume ? &*resume : nullptr;
    hooks.on_checkpoint = [&](flapsim::EvolveCheckpoint c) {
      c.args = opt.spec_args;
      const std::string path = out_dir + "/checkpoint.txt";
      flapsim::writeTextFile(path + ".tmp", flapsim::checkpointToText(c));
      std::filesystem::rename(path + ".tmp", path);
    };
    hooks.on_generation = [&](const flapsim::GenerationStats& g) {
      const auto now = Clock::now();
      const double elapsed = std::chrono::duration<double>(now - start).count();
      const double dt = std::chrono::duration<double>(now - last).count();
      last = now;
      const int episodes = g.evaluations * params.episode.episodes;
      const double rate = dt > 0.0 ? episodes / dt : 0.0;
      const double left =
          elapsed / (g.generation + 1 - first) * (params.ga.generations - g.generation);
      const int workers = farm ? farm->workersUp() : params.ga.threads;
      std::printf(
          "generation %3d/%d  best %8.4f  mean %8.4f  %6.1f episodes/s  %d %s  elapsed %s  left "
          "~%s\n",
          g.generation, params.ga.generations, g.best, g.mean, rate, workers,
          farm ? "workers" : "threads", formatDuration(elapsed).c_str(),
          formatDuration(left).c_str());
      std::fflush(stdout);
      if (progress) {
        flapsim::FarmProgress msg;
        msg.generation = g.generation;
        msg.generations = params.ga.generations;
        msg.best = g.best;
        msg.mean = g.mean;
        msg.episodes = episodes;
        msg.episodes_per_second = rate;
        msg.workers_up = workers;
        msg.seconds_left = left;
        progress->publish(msg);
      }
    };
    const flapsim::EvolveResult result = flapsim::evolveFlapController(params, hooks);
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
        {"threads", std::to_string(params.ga.threads)},
        {"evaluated_on", farm ? "farm" : "in process"}};
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
                            flapsim::episodeStarts(episode, model.get()).front(), true);
    flapsim::writeTextFile(out_dir + "/rates.csv", flapsim::ratesCsv(ep.trace));
    std::printf(
        "best fitness %.4f (generation 0: %.4f), wall time %.1f s; wrote %s, %s/fitness.csv,"
        " %s/rates.csv\n",
        result.best_fitness, result.history.front().best, wall, weights_path.c_str(),
        out_dir.c_str(), out_dir.c_str());

    if (opt.plot) {
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
