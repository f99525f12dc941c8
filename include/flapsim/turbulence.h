// Air that is not steady: Dryden turbulence for low altitude (MIL-F-8785C; MIL-HDBK-1797 is the
// same spectra with its transverse and vertical scale lengths halved) and the discrete
// 1-cosine gust. Both add to the steady wind (AirParams::wind); the world samples them for
// each creature at the start of each step (World::airVelocity). No clock, no state: a field
// is a function of position and time, so a run, a reset and a rerun give the same bits.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "flapsim/types.h"

namespace flapsim {

/// Dryden turbulence carried by the steady wind. The field varies along the steady wind's
/// horizontal direction (x if there is none): a creature at x samples it at xi = d . (x - W t),
/// as MIL-F-8785C's spectra are taken along the path through the air mass. Components: u along
/// d, v across it (z x d), w up. Intensities (low altitude, h in ft): sigma_w = 0.1 W20,
/// sigma_u = sigma_v = sigma_w / (0.177 + 0.000823 h)^0.4; scale lengths L_w = h, L_u = L_v =
/// h / (0.177 + 0.000823 h)^1.2.
///
/// The air mass's eddies live and die (unless `frozen`): independent realisations F_m of the
/// spectra are born every D seconds, each living 2 D, and the field is
/// cos(pi u / 2) F_m(xi) + sin(pi u / 2) F_m+1(xi) at t = (m + u) D. At every instant it is a
/// Dryden field (variance sigma^2, spectra in space unchanged); a creature that stays in the
/// same air (drifting with the wind) feels it decorrelate as c(tau) = ((2D - tau) cos(a tau) +
/// sin(a tau) / a) / 2D, a = pi / 2D, over 2D, whose integral time is T_L = lagrangianTime()
/// (Hanna 1982, the neutral surface layer): D = pi^2 T_L / 8. Frozen (Taylor's hypothesis,
/// MIL-F-8785C's premise: a flier much faster than the gusts) a drifting creature would feel
/// the same gust for ever.
struct TurbulenceParams {
  /// m/s, W20: the wind 6 m (20 ft) above the ground that sets the intensities. 0: none.
  /// turbulenceLevelWind() gives the specification's light, moderate and severe.
  double wind_at_6m = 0.0;
  /// m, the height the intensities and scale lengths are taken at, within the model's
  /// low-altitude range [kMinTurbulenceHeight, kMaxTurbulenceHeight].
  double height = 5.0;
  /// false: one field, in space and time, that every creature flies through (two creatures at
  /// the same place feel the same air); true: each creature its own realisation (its seed
  /// mixed with the creature's name).
  bool per_creature = false;
  /// true: Taylor's frozen field, F_0 for ever (the field as it was before its eddies came to
  /// live and die, to the bit); false: the air mass decorrelates over lagrangianTime().
  bool frozen = false;
  std::uint64_t seed = 0;
  bool operator==(const TurbulenceParams& o) const {
    return wind_at_6m == o.wind_at_6m && height == o.height && per_creature == o.per_creature &&
           frozen == o.frozen && seed == o.seed;
  }
  bool operator!=(const TurbulenceParams& o) const { return !(*this == o); }
};

constexpr double kMinTurbulenceHeight = 3.048;  // m, 10 ft
constexpr double kMaxTurbulenceHeight = 304.8;  // m, 1000 ft
constexpr double kMaxTurbulenceWind = 100.0;    // m/s, W20
constexpr int kTurbulenceModes = 512;           // Fourier modes per component

/// W20 of a named intensity: "light" 7.72 m/s (15 kt), "moderate" 15.43 m/s (30 kt), "severe"
/// 23.15 m/s (45 kt), "none" 0. Throws InputError naming the level otherwise.
double turbulenceLevelWind(const std::string& level);

/// W20 of a level named or given in m/s ("light", "7.5"): the tools' --turbulence. Throws
/// InputError naming the text otherwise or outside [0, kMaxTurbulenceWind].
double turbulenceWindFromText(const std::string& text);
/// The same for a tool's flag: an error names the flag first ("--turbulence: ...").
double turbulenceWindFromFlag(const std::string& flag, const std::string& text);

/// The model's intensities (m/s) and scale lengths (m) at a height.
struct DrydenScales {
  Vec3 sigma = Vec3::Zero();   // u, v, w
  Vec3 length = Vec3::Zero();  // L_u, L_v, L_w
};
DrydenScales drydenScales(double wind_at_6m, double height);

/// One-sided spatial power spectral density (m^2/s^2 per rad/m) of component `axis` (0 u,
/// 1 v, 2 w) at spatial frequency `omega` (rad/m): the longitudinal
/// sigma^2 (2L/pi) / (1 + (L omega)^2), the others sigma^2 (L/pi) (1 + 3 (L omega)^2) /
/// (1 + (L omega)^2)^2. Each integrates to sigma^2 over [0, inf).
double drydenSpectrum(const DrydenScales& s, int axis, double omega);
/// The integral of drydenSpectrum over [0, omega] (omega may be infinity).
double drydenVariance(const DrydenScales& s, int axis, double omega);

/// The Lagrangian integral time of the air's velocity at `height` (s): Hanna's (1982) neutral
/// surface-layer T_L = 0.5 h / sigma_w, the same for u, v and w (infinity without turbulence).
double lagrangianTime(const DrydenScales& s, double height);
/// The correlation in time of the air a drifting creature feels, c(tau) above, for a field
/// that decorrelates over `lagrangian_time` (infinity: 1, frozen).
double airMassCorrelation(double tau, double lagrangian_time);

/// One-sided temporal power spectral density ((m/s)^2 per rad/s) of component `axis` felt at
/// angular frequency `omega` (rad/s) by a point moving through the air at `speed` (m/s) along
/// the wind, in a field that decorrelates over `lagrangian_time` (s): (2 / pi) times the cosine
/// transform of R(speed tau) c(tau), R the model's correlation in space (longitudinal sigma^2
/// exp(-r / L), the others sigma^2 (1 - r / 2L) exp(-r / L)), by quadrature. Frozen (infinity)
/// and moving: drydenSpectrum(omega / speed) / speed.
double drydenFeltSpectrum(const DrydenScales& s, int axis, double omega, double speed,
                          double lagrangian_time);

/// A realisation F_m: the sum of kTurbulenceModes Fourier modes per component, at frequencies
/// spread log-uniformly from 0.01 / L_max to 100 / L_min (each drawn within its band, the same
/// for every F_m), each band's variance its share of the spectrum (the first band reaching down
/// to 0, the last up to infinity, so the variance is sigma^2), random phases (F_0's drawn with
/// the frequencies from the realisation seed, F_m's from their own). Evaluated on a grid along
/// the path (L_min / 500 apart, computed in chunks as they are first needed, a bounded number
/// kept) and interpolated linearly: the same value wherever and whenever it is asked for.
class TurbulenceField {
 public:
  TurbulenceField() = default;  // none: zero everywhere
  /// Throws InputError for parameters outside their ranges.
  TurbulenceField(const TurbulenceParams& params, std::uint64_t realisation_seed);
  bool active() const { return !omega_.empty(); }
  const DrydenScales& scales() const { return scales_; }
  /// s: the time over which the air mass decorrelates (infinity if frozen).
  double lagrangianTime() const { return lagrangian_time_; }
  /// (u, v, w) at path coordinate xi (m) at `time` (s; before 0: as at 0).
  Vec3 componentsAt(double xi, double time) const;
  /// The field's velocity (world frame) felt at `position` at `time` in a steady `wind`.
  Vec3 velocity(const Vec3& position, double time, const Vec3& wind) const;

 private:
  // Grid intervals per chunk: F_0's as the frozen field's always were; F_m's (m > 0) shorter,
  // since each lives 2 D and a creature crosses few metres of air in that time.
  static constexpr int kChunk = 1024;
  static constexpr int kLivingChunk = 128;
  static constexpr size_t kChunksKept = 64;
  static constexpr size_t kRealisationsKept = 3;
  // F_m's phases and the chunks of its grid made so far (chunk + 1 points each).
  struct Realisation {
    int chunk = kChunk;
    std::vector<Vec3> cos_amplitude, sin_amplitude;  // per mode: a cos(phi), -a sin(phi)
    std::map<std::int64_t, std::vector<Vec3>> chunks;
  };
  Realisation& realisation(std::int64_t m) const;
  // Mode k's component `axis` of r at `phase`, with the mode's amplitude.
  void setPhase(Realisation& r, size_t k, int axis, double phase) const;
  const std::vector<Vec3>& chunk(Realisation& r, std::int64_t index) const;
  Vec3 realisationAt(Realisation& r, double xi) const;

  DrydenScales scales_;
  double spacing_ = 0.0;          // m, of the grid
  double lagrangian_time_ = 0.0;  // s
  double renewal_ = 0.0;          // s, D
  std::uint64_t seed_ = 0;
  std::vector<double> omega_;    // rad/m, per mode
  std::vector<Vec3> amplitude_;  // per mode and component: sqrt(2 x its band's variance)
  mutable std::map<std::int64_t, Realisation> realisations_;
};

/// The realisation seed of a creature: the field's seed, mixed with the name if per_creature.
std::uint64_t turbulenceSeed(const TurbulenceParams& params, const std::string& creature);

/// The discrete 1-cosine gust (MIL-F-8785C's shape, in time): from `start` it rises as
/// velocity (1 - cos(pi tau / rise)) / 2 over `rise` s, holds for `hold` s (< 0: for ever),
/// then falls back the same way. Zero velocity: none.
struct DiscreteGust {
  Vec3 velocity = Vec3::Zero();  // m/s, world frame, at its peak
  double start = 0.0;            // s of sim time
  double rise = 1.0;             // s, > 0
  double hold = -1.0;            // s; < 0: it stays
};
constexpr double kMaxGustSpeed = 1e3;  // m/s, each component
Vec3 gustVelocity(const DiscreteGust& gust, double time);

/// Empty if valid, else a message naming the parameter (air/turbulence/..., air/gust/...).
std::string checkTurbulence(const TurbulenceParams& params);
std::string checkGust(const DiscreteGust& gust);

}  // namespace flapsim
