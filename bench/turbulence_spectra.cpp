// The turbulence a creature feels, against the model it was made from: a plate held at rest
// (no gravity, air density 0) at 5 m in a steady 1 m/s wind and Dryden turbulence of a given
// level, the air's velocity at it (World::airVelocity) sampled every 0.05 s for 2^18 samples
// (3.6 h of sim time, 36 km of air going by), Welch's spectra (segments of 2^13 samples) of its
// three components against the model's, the spectrum in space seen through the air mass's
// decorrelation in time (flapsim::drydenFeltSpectrum; frozen it would be S(f) = 2 pi
// Phi(2 pi f / U) / U per Hz), each averaged over sixth-octave bands. Prints a CSV (the band's
// centre in Hz; measured and model densities of u, v, w in (m/s)^2/Hz) and, on stderr, each
// component's variance against sigma^2. bench/turbulence_spectra.sh plots it.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/spectrum.h"
#include "flapsim/turbulence.h"
#include "flapsim/world.h"

int main(int argc, char** argv) {
  using namespace flapsim;
  const std::string level = argc > 1 ? argv[1] : "light";
  if (argc > 2 || level == "--help" || level == "-h") {
    std::fprintf(stderr, "usage: turbulence_spectra [none|light|moderate|severe] > spectra.csv\n");
    return argc > 2 ? 2 : 0;
  }
  try {
    WorldParams p;
    p.ground = false;
    p.gravity = Vec3::Zero();
    p.step_size = 0.01;
    p.air.density = 0.0;
    const double speed = 1.0;
    p.air.wind = Vec3(speed, 0.0, 0.0);
    p.air.turbulence.wind_at_6m = turbulenceLevelWind(level);
    p.air.turbulence.height = 5.0;
    World world(p);
    world.spawn("plate", parseCreatureModel(R"(<robot name="plate"><link name="plate">
      <inertial><mass value="0.01"/><inertia ixx="3.3e-5" ixy="0" ixz="0" iyy="3.3e-5" iyz="0"
      izz="6.7e-5"/></inertial><collision><geometry><box size="0.2 0.2 0.002"/></geometry>
      </collision></link></robot>)"),
                Pose{Vec3(0.0, 0.0, 5.0), Quat::Identity()});
    const int count = 1 << 18, every = 5;
    const double spacing = every * p.step_size;
    std::vector<std::vector<double>> samples(3, std::vector<double>(count));
    for (int i = 0; i < count; ++i) {
      const Vec3 v = world.airVelocity("plate") - p.air.wind;
      for (int axis = 0; axis < 3; ++axis) samples[axis][i] = v[axis];
      world.step(every);
    }
    const DrydenScales scales = drydenScales(p.air.turbulence.wind_at_6m, p.air.turbulence.height);
    const double t_l = lagrangianTime(scales, p.air.turbulence.height);
    std::vector<Spectrum> spectra;
    for (int axis = 0; axis < 3; ++axis) {
      spectra.push_back(welchSpectrum(samples[axis], spacing, 1 << 13));
      double mean = 0.0, square = 0.0;
      for (double x : samples[axis]) mean += x / count;
      for (double x : samples[axis]) square += (x - mean) * (x - mean) / count;
      std::fprintf(stderr, "%c: variance %.4f (m/s)^2, model sigma^2 %.4f, ratio %.3f; L %.1f m\n",
                   "uvw"[axis], square, scales.sigma[axis] * scales.sigma[axis],
                   square / (scales.sigma[axis] * scales.sigma[axis]), scales.length[axis]);
      if (axis == 2) std::fprintf(stderr, "Lagrangian time T_L %.2f s\n", t_l);
    }
    // Sixth-octave bands: the field is a sum of tones (32 an octave), a line spectrum bin by
    // bin at high frequency; band by band it is the model's.
    std::vector<Spectrum> models = spectra;
    for (int axis = 0; axis < 3; ++axis) {
      for (size_t k = 0; k < models[axis].frequency.size(); ++k) {
        models[axis].density[k] =
            drydenFeltSpectrum(scales, axis, models[axis].frequency[k], speed, t_l);
      }
    }
    std::printf("frequency_hz,u,u_model,v,v_model,w,w_model\n");
    const double top = spectra[0].frequency.back();
    for (double low = spectra[0].frequency[1]; low * std::pow(2.0, 1.0 / 6.0) <= top;
         low *= std::pow(2.0, 1.0 / 6.0)) {
      const double high = low * std::pow(2.0, 1.0 / 6.0);
      std::printf("%.6g", std::sqrt(low * high) / (2.0 * M_PI));
      // per Hz: 2 pi times the density per rad/s
      for (int axis = 0; axis < 3; ++axis) {
        std::printf(",%.6g,%.6g", 2.0 * M_PI * bandDensity(spectra[axis], low, high),
                    2.0 * M_PI * bandDensity(models[axis], low, high));
      }
      std::printf("\n");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "turbulence_spectra: %s\n", e.what());
    return 1;
  }
  return 0;
}
