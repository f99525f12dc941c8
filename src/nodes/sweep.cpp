// sweep: the paper's Fig. 14-15 experiment. Prints, per inclination, the average pressure on
// a plate in a steady flow and its lift and drag, for each air model, drag coefficient and
// grid; writes a CSV and, when gnuplot is installed, a PNG plot.
#include "flapsim/sweep.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include "flapsim/text_file.h"
#include "flapsim/types.h"

int main(int argc, char** argv) {
  flapsim::SweepParams p;
  std::string out_dir = "out/sweep";
  flapsim::CliParser cli = flapsim::sweepCli(p, out_dir);
  try {
    const std::vector<flapsim::CliSeen> seen =
        cli.parse(std::vector<std::string>(argv + 1, argv + argc));
    const std::string unused = flapsim::sweepUnusedFlag(p, seen);
    if (!unused.empty()) throw flapsim::InputError(unused);
  } catch (const std::exception& e) {
    std::cerr << "sweep: " << e.what() << "\n" << cli.usage();
    return 2;
  }
  if (cli.help()) {
    std::cout << cli.usage();
    return 0;
  }
  try {
    const auto rows = flapsim::pressureSweep(p);
    std::cout << flapsim::sweepTable(p, rows);
    std::filesystem::create_directories(out_dir);
    const std::string csv = out_dir + "/sweep.csv", png = out_dir + "/sweep.png";
    flapsim::writeTextFile(csv, flapsim::sweepCsv(rows));
    std::cout << "wrote " << csv << std::endl;
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
      std::cerr << "sweep: gnuplot not found, no plot (apt-get install gnuplot-nox)\n";
      return 0;
    }
    FILE* pipe = popen("gnuplot", "w");
    if (!pipe) throw std::runtime_error("cannot start gnuplot");
    std::fputs(flapsim::sweepGnuplotScript(p, rows, csv, png).c_str(), pipe);
    if (pclose(pipe) != 0) throw std::runtime_error("gnuplot failed");
    std::cout << "wrote " << png << "\n";
  } catch (const std::exception& e) {
    std::cerr << "sweep: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
