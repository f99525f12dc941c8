#include "flapsim/hover_evolution.h"

#include <algorithm>
#include <cmath>

#include "flapsim/flight_check.h"

namespace flapsim {

const std::vector<HoverGene>& hoverGenes() {
  using P = HoverControllerParams;
  static const std::vector<HoverGene> genes = [] {
    const P hand;
    std::vector<HoverGene> g = {{"trim_frequency", &P::trim_frequency, 0.5},
                                {"amplitude", &P::amplitude, 0.3},
                                {"feather", &P::feather, 0.3},
                                {"height_gain", &P::height_gain, 1.0},
                                {"climb_damping", &P::climb_damping, 1.0},
                                {"height_integral", &P::height_integral, 1.0},
                                {"roll_gain", &P::roll_gain, 1.0},
                                {"roll_damping", &P::roll_damping, 1.0},
                                {"pitch_gain", &P::pitch_gain, 1.0},
                                {"pitch_damping", &P::pitch_damping, 1.0},
                                {"attitude_integral", &P::attitude_integral, 1.0},
                                {"position_gain", &P::position_gain, 1.0},
                                {"position_integral", &P::position_integral, 1.0},
                                {"velocity_gain", &P::velocity_gain, 1.0},
                                {"start_time", &P::start_time, 1.0},
                                {"start_amplitude", &P::start_amplitude, 0.4 / 0.6}};
    for (HoverGene& gene : g) gene.span *= hand.*gene.member;  // a fraction of the value
    return g;
  }();
  return genes;
}

std::string checkHoverGenes(const std::vector<double>& genes) {
  if (genes.size() != static_cast<size_t>(kHoverGeneCount)) {
    return std::to_string(genes.size()) + " genes, the hover controller has " +
           std::to_string(kHoverGeneCount);
  }
  for (size_t i = 0; i < genes.size(); ++i) {
    if (!std::isfinite(genes[i]) || std::abs(genes[i]) > kHoverGeneRange) {
      return "gene " + std::to_string(i) + " (" + hoverGenes()[i].name + ") is not a number in " +
             "[-1, 1]";
    }
  }
  return "";
}

HoverControllerParams hoverParamsFromGenes(const std::vector<double>& genes, double altitude) {
  const std::string err = checkHoverGenes(genes);
  if (!err.empty()) throw InputError("hover genome: " + err);
  HoverControllerParams p;
  p.altitude = altitude;
  for (size_t i = 0; i < genes.size(); ++i) {
    const HoverGene& g = hoverGenes()[i];
    p.*g.member += genes[i] * g.span;
  }
  return p;
}

std::vector<double> hoverGenesFromParams(const HoverControllerParams& params) {
  const HoverControllerParams hand;
  std::vector<double> genes;
  for (const HoverGene& g : hoverGenes()) {
    genes.push_back((params.*g.member - hand.*g.member) / g.span);
  }
  return genes;
}

double hoverPowerTerm(double specific_power, double weight) {
  return std::min(weight * specific_power / 100.0, kHoverMaxTerm);
}

double hoverEpisodeFitness(const HoverFlightResult& r, double flip_penalty) {
  const double rms = std::isfinite(r.altitude_rms) && !r.flipped
                         ? std::min(r.altitude_rms, kHoverMaxTerm)
                         : kHoverMaxTerm;
  const double power = hoverPowerTerm(r.specificPower(), kHoverPowerWeight);
  const double tilt = kHoverTiltWeight * std::max(0.0, kHoverMinUpright - r.min_upright);
  const double start_limit = std::cos(std::min(r.start_tilt + kHoverStartTilt, M_PI));
  const double start_tilt = kHoverStartTiltWeight * std::max(0.0, start_limit - r.lowest_upright);
  const double sag = kHoverSagWeight * std::clamp(r.start_sag - kHoverMaxSag, 0.0, kHoverMaxTerm);
  return -(rms + power + tilt + start_tilt + sag + (r.flipped ? flip_penalty : 0.0));
}

double hoverFitnessBound(const EpisodeParams& params) {
  return 2.0 * kHoverMaxTerm + kHoverTiltWeight * (kHoverMinUpright + 1.0) +
         kHoverStartTiltWeight * 2.0 + kHoverSagWeight * kHoverMaxTerm + params.flip_penalty;
}

std::string validateHoverEpisodes(const EpisodeParams& params) {
  if (params.settle_time < params.duration) return "";
  return "the hover episodes' settling time must be shorter than their duration (--settle)";
}

HoverFlightParams hoverEpisodeFlight(const EpisodeParams& params, const EpisodeStart& start,
                                     double altitude) {
  HoverFlightParams f;
  f.duration = params.duration;
  f.settle = params.settle_time;
  f.world = params.world;
  if (start.step_size > 0.0) f.world.step_size = start.step_size;
  f.world.air.wind = start.wind;
  f.world.air.turbulence = episodeTurbulence(params.world.air.turbulence, start, altitude);
  f.start_roll = start.roll;
  f.start_pitch = start.pitch;
  f.start_height = params.start_height;
  f.imu_noise = params.imu_noise;
  f.noise_seed = start.noise_seed;
  f.end_on_flip = true;
  return f;
}

HoverFlightResult runHoverEpisode(const CreatureModelPtr& model,
                                  const HoverControllerParams& controller,
                                  const EpisodeParams& params, const EpisodeStart& start) {
  HoverControllerParams c = controller;
  c.altitude = start.altitude.value_or(controller.altitude);
  HoverFlightParams f = hoverEpisodeFlight(params, start, c.altitude);
  if (params.real_air) {
    // Real air's impulses sized to this creature, with the gyro bias and altimeter noise.
    f.gusts = realAirGusts(params, *model);
    f.gust_start = start;
  }
  return flyHover(model, c, f);
}

EvolveParams hoverPreset() {
  EvolveParams p;
  p.kind = EvolveKind::kHover;
  p.ga.population = 16;
  p.ga.generations = 20;
  p.ga.mutation_rate = 0.15;
  p.ga.gene_min = -kHoverGeneRange;
  p.ga.gene_max = kHoverGeneRange;
  EpisodeParams& e = p.episode;
  e.duration = 12.0;
  e.settle_time = 4.0;
  e.start_height = 3.0;
  e.min_roll = 0.0;
  e.max_roll = 0.3;
  e.max_pitch = 0.3;
  e.max_wind = 1.0;
  e.altitude_hold = true;
  e.min_altitude = 2.7;
  e.max_altitude = 3.3;
  e.flip_penalty = 20.0;
  e.episodes = 6;
  e.first_start_level = true;
  return p;
}

}  // namespace flapsim
