// evolve: runs the GA on the flap-unit network headless and writes the best
// weights (YAML), fitness per generation (CSV), the best individual's wing
// rates over an episode (CSV) and two PNG plots (gnuplot). See --help.
#include <algorithm>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "flapsim/evolve_tool.h"
#include "flapsim_ros/evolve_session.h"

int main(int argc, char** argv) {
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::vector<std::string> args(argv + 1, argv + argc);
  flapsim::EvolveOptions opt;
  std::optional<flapsim::EvolveCheckpoint> resume;
  try {
    opt = flapsim::resolveEvolveOptions(args, threads, resume);
  } catch (const std::exception& e) {
    std::cerr << "evolve: " << e.what() << "\n" << flapsim::evolveUsage(args, threads);
    return 2;
  }
  if (opt.help) {
    std::cout << flapsim::evolveUsage(args, threads);
    return 0;
  }
  try {
    flapsim_ros::EvolveSession session(argc, argv, opt, resume);
    const flapsim::EvolveResult result = session.run();
    std::cout << flapsim::writeEvolveOutputs(opt, result, session.elapsed(), session.evaluatedOn())
              << session.droppedReport() << std::flush;
  } catch (const std::exception& e) {
    std::cerr << "evolve: " << e.what() << "\n";
    return 1;
  }
  const bool rates = opt.params.kind == flapsim::EvolveKind::kFlap;
  const bool front = opt.params.kind == flapsim::EvolveKind::kMorph;
  if (opt.plot && !flapsim::plotEvolveOutputs(opt.out_dir, rates, front)) {
    std::cerr << "evolve: gnuplot failed (apt package gnuplot-nox); no plots\n";
    return 1;
  }
  if (opt.plot) {
    std::cout << "wrote " << opt.out_dir << "/fitness.png"
              << (rates ? ", " + opt.out_dir + "/rates.png" : std::string())
              << (front ? ", " + opt.out_dir + "/front.png" : std::string()) << "\n";
  }
  return 0;
}
