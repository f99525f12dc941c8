// sweep: the paper's Fig. 14-15 experiment. Prints, per inclination, the average pressure on
// a plate in a steady flow and its lift and drag, for each air model, drag coefficient and
// grid; writes a CSV and, when gnuplot is installed, a PNG plot.
#include "flapsim/sweep.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

namespace {

template <typename T>
std::vector<T> parseList(const std::string& text) {
  std::vector<T> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::stringstream one(item);
    T value;
    if (!(one >> value)) throw std::invalid_argument("bad list item '" + item + "'");
    out.push_back(value);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  flapsim::SweepParams p;
  std::string out_dir = "out/sweep";
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--help" || a == "-h") {
        std::cout << "usage: sweep [--speed M_S] [--cd 2.0,1.15] [--grid 4,8] "
                     "[--models pressure,quasi_steady] [--step DEG] [--out DIR]\n";
        return 0;
      }
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      const std::string v = argv[++i];
      if (a == "--speed") {
        p.speed = std::stod(v);
      } else if (a == "--cd") {
        p.drag_coefficients = parseList<double>(v);
      } else if (a == "--grid") {
        p.grids = parseList<int>(v);
      } else if (a == "--models") {
        p.models = parseList<std::string>(v);
      } else if (a == "--step") {
        p.step_deg = std::stod(v);
      } else if (a == "--out") {
        out_dir = v;
      } else {
        throw std::invalid_argument("unknown argument '" + a + "'");
      }
    }
    const auto rows = flapsim::pressureSweep(p);
    std::printf(
        "plate %.2f x %.2f m in a %.1f m/s flow (rho %.3f): average pressure on the plate\n",
        p.chord, p.span, p.speed, p.density);
    std::printf("%-13s %5s %4s %7s %12s %10s %10s\n", "model", "Cd", "grid", "incl", "pressure/Pa",
                "lift/N", "drag/N");
    for (const auto& r : rows) {
      std::printf("%-13s %5.2f %4d %7.1f %12.3f %10.4f %10.4f\n", r.model.c_str(),
                  r.drag_coefficient, r.grid, r.inclination_deg, r.pressure, r.lift, r.drag);
    }
    std::system(("mkdir -p '" + out_dir + "'").c_str());
    const std::string csv = out_dir + "/sweep.csv", png = out_dir + "/sweep.png";
    std::ofstream(csv) << flapsim::sweepCsv(rows);
    std::printf("wrote %s\n", csv.c_str());
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
      std::fprintf(stderr, "sweep: gnuplot not found, no plot (apt-get install gnuplot-nox)\n");
      return 0;
    }
    // One curve per (model, Cd, grid): their rows are contiguous in the CSV.
    std::ostringstream gp;
    gp << "set datafile separator ','\nset terminal pngcairo size 900,600 noenhanced\n"
       << "set output '" << png << "'\nset title 'Average pressure on a " << p.chord << " x "
       << p.span << " m plate in a " << p.speed << " m/s flow (paper Fig. 15)'\n"
       << "set xlabel 'inclination (deg; 0 = edge-on, 90 = face-on)'\n"
       << "set ylabel 'average pressure (Pa)'\nset xrange [0:180]\nset xtics 15\nset grid\n"
       << "set key top left\nplot ";
    for (size_t first = 0; first < rows.size();) {
      size_t last = first;
      while (last + 1 < rows.size() &&
             rows[last + 1].inclination_deg > rows[last].inclination_deg) {
        ++last;
      }
      char title[96];
      std::snprintf(
          title, sizeof(title), "%s%s, grid %d", rows[first].model.c_str(),
          rows[first].model == "pressure"
              ? (" Cd " + std::to_string(rows[first].drag_coefficient).substr(0, 4)).c_str()
              : "",
          rows[first].grid);
      gp << (first ? ", " : "") << "'" << csv << "' skip 1 every ::" << first << "::" << last
         << " using 4:6 with linespoints title '" << title << "'";
      first = last + 1;
    }
    gp << "\n";
    FILE* pipe = popen("gnuplot", "w");
    if (!pipe) throw std::runtime_error("cannot start gnuplot");
    std::fputs(gp.str().c_str(), pipe);
    if (pclose(pipe) != 0) throw std::runtime_error("gnuplot failed");
    std::printf("wrote %s\n", png.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sweep: %s\n", e.what());
    return 2;
  }
  return 0;
}
