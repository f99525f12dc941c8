// What the benchmarks share: the creatures they time, their options, medians and the table.
// Header-only, for bench/ only.
#pragma once

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace flapsim_bench {

/// A creature of `units` flap units (makeCreatureUrdf), named as in every table.
struct BenchCreature {
  std::string name;
  int units = 1;
};

/// flap_unit and chain_4, chain_6, chain_12, chain_25.
inline std::vector<BenchCreature> benchCreatures() {
  std::vector<BenchCreature> out{{"flap_unit", 1}};
  for (int n : {4, 6, 12, 25}) out.push_back({"chain_" + std::to_string(n), n});
  return out;
}

/// The clock runs are timed with: wall time, or with --cpu-time the CPU time of the
/// calling thread (steps per CPU second: for a machine that is busy with other work).
inline bool& cpuTimeClock() {
  static bool on = false;
  return on;
}
inline double benchSeconds() {
  if (cpuTimeClock()) {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// A whole positive count (1..1e6); false if `s` is anything else.
inline bool parseCount(const char* s, int* out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < 1 || v > 1000000) return false;
  *out = static_cast<int>(v);
  return true;
}

/// A finite duration in (0, 1e5] s; false if `s` is anything else.
inline bool parseSeconds(const char* s, double* out) {
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (end == s || *end != '\0' || !std::isfinite(v) || v <= 0.0 || v > 1e5) return false;
  *out = v;
  return true;
}

struct BenchOptions {
  int runs = 5;
  double seconds = 2.0;
  std::string only;  // a creature name, empty for all
};

/// --runs N --seconds S --only NAME (a name of benchCreatures()) --cpu-time; false on
/// anything else.
inline bool parseBenchOptions(int argc, char** argv, BenchOptions* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) {
      if (!parseCount(argv[++i], &o->runs)) return false;
    } else if (a == "--seconds" && i + 1 < argc) {
      if (!parseSeconds(argv[++i], &o->seconds)) return false;
    } else if (a == "--only" && i + 1 < argc) {
      o->only = argv[++i];
    } else if (a == "--cpu-time") {
      cpuTimeClock() = true;
    } else {
      return false;
    }
  }
  const std::vector<BenchCreature> all = benchCreatures();
  return o->only.empty() || std::any_of(all.begin(), all.end(),
                                        [o](const BenchCreature& c) { return c.name == o->only; });
}

/// The usage line of a reference benchmark; returns the exit code 2.
inline int referenceUsage(const char* program) {
  std::fprintf(stderr,
               "usage: %s [--runs N] [--seconds S] [--only NAME] [--cpu-time]\n"
               "  NAME: flap_unit, chain_4, chain_6, chain_12 or chain_25\n",
               program);
  return 2;
}

/// The table of the reference benchmarks: steps per second, real-time factor, us per body.
inline void printTableHeader() {
  std::printf("%-14s %7s %14s %10s %14s\n", "creature", "bodies", "steps/s", "RTF", "us/body/step");
}
inline void printTableRow(const std::string& name, int bodies, double steps_per_second,
                          double step_size) {
  std::printf("%-14s %7d %14.0f %10.1f %14.3f\n", name.c_str(), bodies, steps_per_second,
              steps_per_second * step_size, 1e6 / (steps_per_second * bodies));
}

/// The stability probe's verdict (mujoco_bench --check, flapsim_bench --check): a setting
/// counts if over the probe the simulator warned of nothing, every speed stayed finite, the
/// largest speed stayed within kMaxSpeedRatio of the reference's (in MuJoCo 3.12 the runaway
/// settings of flapsim's creatures reach 2.4 to 42 times it: RK4 at 0.125 ms and Euler at 1 ms
/// on the flap unit) and the root's height change after the probe's height time within
/// kMaxHeightError of the reference's (m, or that fraction of the change if larger): the same
/// flight, not merely a bounded one.
constexpr double kMaxSpeedRatio = 2.0;
constexpr double kMaxHeightError = 0.10;

struct ProbeFigures {
  int warnings = 0;
  bool finite = true;
  double max_speed = 0.0;
  double height_change = 0.0;  // m, at the probe's height time
};

/// Empty if `r` counts against the reference `ref`, else why not; `warnings` and `speed` name
/// the simulator's warnings and its speed figure in the message.
inline std::string instability(const ProbeFigures& r, const ProbeFigures& ref, const char* warnings,
                               const char* speed) {
  if (r.warnings > 0) return std::to_string(r.warnings) + " " + warnings;
  if (!r.finite) return "non-finite velocities";
  char why[160];
  if (r.max_speed > kMaxSpeedRatio * ref.max_speed) {
    std::snprintf(why, sizeof(why), "%s %.3g is %.1f x the reference's", speed, r.max_speed,
                  r.max_speed / ref.max_speed);
    return why;
  }
  const double dz = r.height_change, dz_ref = ref.height_change;
  if (std::abs(dz - dz_ref) > kMaxHeightError * std::max(1.0, std::abs(dz_ref))) {
    std::snprintf(why, sizeof(why), "height change %.3f m against the reference's %.3f m", dz,
                  dz_ref);
    return why;
  }
  return "";
}

}  // namespace flapsim_bench
