// The evolve tool apart from its clock and ROS: its options with a resumed run's, the files
// it writes at the end and its progress line. ROS-free; no clock (the caller passes times).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "flapsim/evolve.h"
#include "flapsim/evolve_args.h"

namespace flapsim {

/// parseEvolveArgs(args, threads); with --resume DIR, the checkpoint DIR/checkpoint.txt is
/// read (readCheckpointFile: only the flags that define the run are taken from it) into
/// `resume` and the options are those of its flags, then `--out DIR`, then `args`. Throws
/// InputError naming the flag or the file.
EvolveOptions resolveEvolveOptions(const std::vector<std::string>& args, int threads,
                                   std::optional<EvolveCheckpoint>& resume);

/// "evolve <the flags that define the run>".
std::string evolveCommand(const EvolveOptions& options);

/// One line of progress after generation `g` (of an evolution begun at generation `first`)
/// after `elapsed` s, the last generation having taken `dt` s.
std::string evolveProgressLine(const EvolveOptions& options, const GenerationStats& g, int first,
                               double elapsed, double dt, int workers);
/// Episodes per second of generation `g` that took `dt` s.
double episodesPerSecond(const EvolveOptions& options, const GenerationStats& g, double dt);
/// Seconds left, from the pace so far.
double secondsLeft(const EvolveOptions& options, const GenerationStats& g, int first,
                   double elapsed);

/// Writes the weights YAML, fitness.csv and rates.csv (the best individual on the first
/// evolution episode) of a finished run (--preset hover: the gains file, flapsim/hover_gains.h,
/// and fitness.csv); returns the line that says so.
std::string writeEvolveOutputs(const EvolveOptions& options, const EvolveResult& result,
                               double wall_s, const std::string& evaluated_on);

/// Runs gnuplot on gnuplotScript(out_dir, 5, rates) (with `front`: and morphFrontGnuplot);
/// false if it failed (or is missing).
bool plotEvolveOutputs(const std::string& out_dir, bool rates = true, bool front = false);

}  // namespace flapsim
