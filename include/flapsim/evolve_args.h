// The evolve command line: flags -> EvolveParams and the run's settings. In the
// core so that a farm worker reads the same flags the same way (bit for bit).
// ROS-free; no clock.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "flapsim/evolve.h"

namespace flapsim {

struct EvolveOptions {
  EvolveParams params;
  std::string preset = "robust";
  /// The flags that define the evolution (preset first; no output paths,
  /// threads, farm or resume settings): what a checkpoint stores and what
  /// the farm sends to its workers.
  std::vector<std::string> spec_args;
  std::string out_dir = "evolve_out";
  std::string weights_path;  // empty: out_dir/weights.yaml
  bool plot = true;
  bool help = false;
  std::string resume_dir;      // --resume DIR
  std::string init_path;       // --init FILE: generation 0 seeded with its weights (GaParams)
  std::string init_body_path;  // --init-body FILE (--preset morph): and with its body genes
  // --farm: evaluate on the flapsim_worker nodes under /flapsim_farm.
  bool farm = false;
  double farm_timeout = 60.0;  // s: a call not answered by then is sent elsewhere
  double farm_wait = 120.0;    // s: how long to wait when no worker is up
  int farm_inflight = 4;       // calls in flight per worker
  int farm_batch = 1;          // tasks per call
};

/// Limits of the flags that define an evolution (a checkpoint's `args`, a farm call's spec).
constexpr std::size_t kMaxSpecArgs = 64;
constexpr std::size_t kMaxSpecBytes = 16384;

/// Parses evolve's flags (argv without the program name; roslaunch's
/// `name:=value` arguments are skipped) from one table (flapsim/cli_args.h): every value
/// has a range. `threads` is the default of --threads. Throws InputError naming the bad
/// flag or value.
/// `later_wins`: a flag given again overrides the earlier one (a resumed run's flags followed
/// by the command line's); otherwise a repeated flag is refused by name.
EvolveOptions parseEvolveArgs(const std::vector<std::string>& args, int threads = 1,
                              bool later_wins = false);

/// The usage text (--help), generated from the table: the defaults shown are those of the
/// preset and flags in `args` (robust for none), so of what runs.
std::string evolveUsage(const std::vector<std::string>& args = {}, int threads = 1);

/// Throws InputError unless `spec_args` holds only flags that define an evolution (the
/// preset and the run's settings: no output paths, threads, farm or resume settings), with
/// valid values, within kMaxSpecArgs and kMaxSpecBytes.
void checkSpecArgs(const std::vector<std::string>& spec_args);

/// The EvaluationSpec of a farm request: the spec of parseEvolveArgs(spec_args), after
/// checkSpecArgs.
EvaluationSpec evaluationSpecFromArgs(const std::vector<std::string>& spec_args);

}  // namespace flapsim
