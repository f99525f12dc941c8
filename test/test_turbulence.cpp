// Air that is not steady: Dryden turbulence (MIL-F-8785C, low altitude) and the discrete
// 1-cosine gust. A realisation's spectra and variances are those of the model at every
// instant; the world carries the field with the steady wind, and the air mass decorrelates
// over Hanna's Lagrangian time (a creature drifting with the wind feels its air change as the
// model says; frozen, it would feel no change); it shares the field between creatures or
// gives each its own, replays it after reset, and the air it makes pushes bodies as air does.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "doc_figure.h"
#include "flapsim/evolve.h"
#include "flapsim/flight_check.h"
#include "flapsim/make_creature.h"
#include "flapsim/spectrum.h"
#include "flapsim/turbulence.h"
#include "flapsim/world.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;

constexpr double kKnot = 1852.0 / 3600.0;

TEST(Turbulence, LevelsAreTheSpecificationsWindsAtSixMetres) {
  EXPECT_DOUBLE_EQ(turbulenceLevelWind("none"), 0.0);
  EXPECT_DOUBLE_EQ(turbulenceLevelWind("light"), 15.0 * kKnot);
  EXPECT_DOUBLE_EQ(turbulenceLevelWind("moderate"), 30.0 * kKnot);
  EXPECT_DOUBLE_EQ(turbulenceLevelWind("severe"), 45.0 * kKnot);
  try {
    turbulenceLevelWind("stormy");
    FAIL() << "an unknown level was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'stormy'"), std::string::npos) << e.what();
  }
}

// At 1000 ft the low-altitude formulas meet the medium-altitude model: isotropic, every
// intensity 0.1 W20, every scale length 1000 ft.
TEST(Turbulence, AtAThousandFeetTheLowAltitudeModelIsIsotropic) {
  const DrydenScales s = drydenScales(10.0, 304.8);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(s.sigma[axis], 1.0, 1e-12) << axis;
    EXPECT_NEAR(s.length[axis], 304.8, 1e-9) << axis;
  }
  // Lower down the horizontal gusts are stronger and longer than the vertical (at 5 m:
  // sigma_u / sigma_w = 1 / 0.1905^0.4, L_u / L_w = 1 / 0.1905^1.2).
  const DrydenScales low = drydenScales(10.0, 5.0);
  const double d = 0.177 + 0.000823 * 5.0 / 0.3048;
  EXPECT_NEAR(low.sigma[0] / low.sigma[2], std::pow(d, -0.4), 1e-12);
  EXPECT_NEAR(low.length[0] / low.length[2], std::pow(d, -1.2), 1e-12);
  EXPECT_DOUBLE_EQ(low.length[2], 5.0);
}

// Samples of one component of a realisation along the path, `spacing` apart.
std::vector<std::vector<double>> pathSamples(const TurbulenceField& f, double spacing, int count) {
  std::vector<std::vector<double>> out(3, std::vector<double>(count));
  for (int i = 0; i < count; ++i) {
    const Vec3 v = f.componentsAt(i * spacing, 0.0);
    for (int axis = 0; axis < 3; ++axis) out[axis][i] = v[axis];
  }
  return out;
}

TurbulenceParams lightAtFiveMetres(std::uint64_t seed) {
  TurbulenceParams p;
  p.wind_at_6m = turbulenceLevelWind("light");
  p.height = 5.0;
  p.seed = seed;
  return p;
}

// Each component of a realisation over 13 km of path (0.1 m apart): Welch's estimate of its
// spectrum (segments of 410 m, 11 longitudinal scale lengths) in octave bands from 1 / L to
// 8 rad/m (a quarter of the sampling's Nyquist frequency) against the model's density at the
// same frequencies, and its variance against sigma^2 (the modes hold it all: the first band
// reaches down to 0, the last up to infinity; a finite path sees the longest waves in part).
// Measured over 2 seeds: the three lowest octaves (a few frequencies each, few segments) within
// 10.4 %, the others within 3.0 %; variances within 8 % (u, v; L = 37 m, the path 350 L) and
// 0.7 % (w; L = 5 m). The transverse form in the longitudinal component is off by 35-50 % in these
// bands; sigma_u = sigma_w (no height factor) is off by a factor 3.8 in variance.
TEST(Turbulence, SpectraAndVariancesAreTheModels) {
  const double spacing = 0.1;
  const Vec3 variance_bound(0.1, 0.1, 0.015);
  double low_bands = 0.0, high_bands = 0.0;  // the largest band errors over seeds and axes
  Vec3 variance_error = Vec3::Zero();        // the largest variance errors over the seeds
  for (std::uint64_t seed : {1u, 2u}) {
    const TurbulenceField field(lightAtFiveMetres(seed), seed);
    const std::vector<std::vector<double>> path = pathSamples(field, spacing, 1 << 17);
    for (int axis = 0; axis < 3; ++axis) {
      const Spectrum s = welchSpectrum(path[axis], spacing, 1 << 12);
      Spectrum model = s;
      for (size_t k = 0; k < s.frequency.size(); ++k) {
        model.density[k] = drydenSpectrum(field.scales(), axis, s.frequency[k]);
      }
      int bands = 0;
      for (double low = 1.0 / field.scales().length[axis]; 2.0 * low <= 8.0; low *= 2.0, ++bands) {
        const double ratio = bandDensity(s, low, 2 * low) / bandDensity(model, low, 2 * low);
        double& worst = bands < 3 ? low_bands : high_bands;
        worst = std::max(worst, std::abs(ratio - 1.0));
        EXPECT_NEAR(ratio, 1.0, bands < 3 ? 0.12 : 0.04)
            << "seed " << seed << " axis " << axis << " band " << low;
      }
      EXPECT_GE(bands, 5) << axis;
      const std::vector<double>& x = path[axis];
      double mean = 0.0, square = 0.0;
      for (double v : x) mean += v;
      mean /= x.size();
      for (double v : x) square += (v - mean) * (v - mean);
      const double sigma2 = field.scales().sigma[axis] * field.scales().sigma[axis];
      EXPECT_NEAR(square / x.size() / sigma2, 1.0, variance_bound[axis])
          << "seed " << seed << " axis " << axis;
      variance_error[axis] =
          std::max(variance_error[axis], std::abs(square / x.size() / sigma2 - 1.0));
    }
  }
  test::printFigure("lowest_three_octaves_error", low_bands);
  test::printFigure("higher_octaves_error", high_bands);
  for (int axis = 0; axis < 3; ++axis) {
    test::printFigure(test::figureName("variance_error_%c", "uvw"[axis]), variance_error[axis]);
  }
}

// A plate at rest (no gravity) in air, a steady wind and light turbulence.
WorldParams turbulentAir(bool per_creature) {
  WorldParams p = test::openSky();
  p.gravity = Vec3::Zero();
  p.air.density = 0.0;  // the air moves nothing: the creature stays where it is put
  p.air.wind = Vec3(0.6, 0.8, 0.0);
  p.air.turbulence = lightAtFiveMetres(7);
  p.air.turbulence.per_creature = per_creature;
  return p;
}

std::vector<Vec3> feltAir(World& w, const std::string& name, int steps, int every) {
  std::vector<Vec3> out;
  for (int i = 0; i < steps; ++i) {
    if (i % every == 0) out.push_back(w.airVelocity(name));
    w.step();
  }
  return out;
}

// One field: two creatures at the same place feel the same air, frozen or living; frozen, one
// 3 m downwind feels it 3 m / |W| = 3 s later. Per creature: two creatures at the same place
// feel different air. Either way a reset replays the same air to the bit.
TEST(Turbulence, OneFrozenFieldIsSharedAndPerCreatureFieldsDiffer) {
  const CreatureModelPtr plate = test::loadUrdf("plate.urdf");
  WorldParams frozen_air = turbulentAir(false);
  frozen_air.air.turbulence.frozen = true;
  World frozen(frozen_air);
  frozen.spawn("a", plate, at(0, 0, 5));
  frozen.spawn("b", plate, at(0, 0, 5));
  frozen.spawn("downwind", plate, at(1.8, 2.4, 5));  // 3 m along (0.6, 0.8)
  const std::vector<Vec3> a = feltAir(frozen, "a", 4000, 1000);
  frozen.reset();
  EXPECT_EQ(feltAir(frozen, "b", 4000, 1000), a);
  frozen.reset();
  frozen.step(1000);
  const Vec3 downwind_later = frozen.airVelocity("downwind");
  frozen.reset();
  // The creature 3 m downwind meets at t + 3 s the air that the first met at t.
  frozen.step(4000);
  EXPECT_LT((frozen.airVelocity("downwind") - a[1]).norm(), 1e-9);
  EXPECT_GT((downwind_later - a[1]).norm(), 1e-3);

  auto twoAtOnePlace = [&](World& w) {
    w.spawn("a", plate, at(0, 0, 5));
    w.spawn("b", plate, at(0, 0, 5));
  };
  World living(turbulentAir(false));
  twoAtOnePlace(living);
  const std::vector<Vec3> living_a = feltAir(living, "a", 4000, 1000);
  living.reset();
  EXPECT_EQ(feltAir(living, "b", 4000, 1000), living_a);
  EXPECT_NE(living_a, a);  // F_0 at t = 0, then other air

  World own(turbulentAir(true));
  twoAtOnePlace(own);
  const std::vector<Vec3> first = feltAir(own, "a", 4000, 1000);
  own.reset();
  EXPECT_EQ(feltAir(own, "a", 4000, 1000), first);
  own.reset();
  const std::vector<Vec3> other = feltAir(own, "b", 4000, 1000);
  for (size_t i = 0; i < first.size(); ++i) EXPECT_GT((first[i] - other[i]).norm(), 1e-3) << i;
}

// Taylor's hypothesis, MIL-F-8785C's premise, in a frozen field (air/turbulence/frozen): a
// creature carried by the steady wind stays in the same air and feels no change, while one at
// rest feels the field go by.
TEST(Turbulence, InAFrozenFieldACreatureDriftingWithTheWindFeelsNoChange) {
  const CreatureModelPtr plate = test::loadUrdf("plate.urdf");
  WorldParams frozen = turbulentAir(false);
  frozen.air.turbulence.frozen = true;
  World w(frozen);
  Twist drift;
  drift.linear = w.params().air.wind;
  w.spawn("drifting", plate, at(0, 0, 5), drift);
  w.spawn("resting", plate, at(0, 0, 5));
  const std::vector<Vec3> drifting = feltAir(w, "drifting", 20000, 1000);
  w.reset();
  const std::vector<Vec3> resting = feltAir(w, "resting", 20000, 1000);
  double moved = 0.0, drifted = 0.0;
  for (size_t i = 1; i < drifting.size(); ++i) {
    EXPECT_LT((drifting[i] - drifting[0]).norm(), 1e-9) << i;
    moved = std::max(moved, (resting[i] - resting[0]).norm());
    drifted = std::max(drifted, (drifting[i] - drifting[0]).norm());
  }
  test::printFigure("drifting_change", drifted);
  test::printFigure("resting_change", moved);
  // light at 5 m: sigma_u 1.5 m/s over 20 m of air (L_u 37 m, L_w 5 m)
  EXPECT_GT(moved, 0.2);
}

// The field's eddies live and die: air that stays at one place in the air mass (as a creature
// drifting with the wind does) decorrelates as c(tau), integral time T_L = 0.5 h / sigma_w
// (Hanna 1982: 3.24 s at 5 m in light turbulence), with the model's variance: not one gust for
// ever. Measured at one point of the air mass every 0.1 s over 20,000 s (about 2,500
// independent stretches of 2D = 8 s): each component's variance within 8 % of sigma^2 (its
// standard error about 3 %), the correlation of w at T_L / 2, T_L and 2 T_L within 0.05 of
// c(tau) (its standard error about 0.02).
TEST(Turbulence, AirThatStaysInTheAirMassDecorrelatesOverTheLagrangianTime) {
  const TurbulenceField field(lightAtFiveMetres(11), 11);
  const DrydenScales s = field.scales();
  const double t_l = field.lagrangianTime();
  EXPECT_NEAR(t_l, 0.5 * 5.0 / (0.1 * 15.0 * kKnot), 1e-12);
  const double every = 0.1;
  const int count = 200000;
  std::vector<Vec3> felt(count);
  for (int i = 0; i < count; ++i) felt[i] = field.componentsAt(0.0, i * every);
  Vec3 mean = Vec3::Zero(), variance = Vec3::Zero();
  for (const Vec3& v : felt) mean += v / count;
  for (const Vec3& v : felt) variance += (v - mean).cwiseProduct(v - mean) / count;
  for (int axis = 0; axis < 3; ++axis) {
    const double ratio = variance[axis] / (s.sigma[axis] * s.sigma[axis]);
    test::printFigure(test::figureName("variance_ratio_%c", "uvw"[axis]), ratio);
    EXPECT_NEAR(ratio, 1.0, 0.08) << axis;
  }
  for (double lag : {0.5 * t_l, t_l, 2.0 * t_l}) {
    const int k = static_cast<int>(std::lround(lag / every));
    double c = 0.0;
    for (int i = 0; i + k < count; ++i)
      c += (felt[i].z() - mean.z()) * (felt[i + k].z() - mean.z());
    c /= (count - k) * variance.z();
    const double model = airMassCorrelation(k * every, t_l);
    test::printFigure(test::figureName("correlation_at_%.1f_s", k * every), c);
    test::printFigure(test::figureName("model_at_%.1f_s", k * every), model);
    EXPECT_NEAR(c, model, 0.05) << "lag " << k * every << " s";
  }
}

// In the world a creature drifting with the wind stays at one point of the air mass and feels
// that point's air as it changes (to rounding), no longer its first value: 20 s of drift move
// its air by more than sigma_w.
TEST(Turbulence, ACreatureDriftingWithTheWindFeelsItsAirMassChange) {
  const CreatureModelPtr plate = test::loadUrdf("plate.urdf");
  const WorldParams p = turbulentAir(false);
  World w(p);
  Twist drift;
  drift.linear = p.air.wind;
  w.spawn("drifting", plate, at(0, 0, 5), drift);
  const TurbulenceField field(p.air.turbulence, turbulenceSeed(p.air.turbulence, "drifting"));
  const std::vector<Vec3> felt = feltAir(w, "drifting", 20000, 1000);
  double changed = 0.0;
  for (size_t i = 0; i < felt.size(); ++i) {
    const double t = static_cast<double>(i);  // s: a sample every 1000 steps of 1 ms
    const Vec3 at_it = Vec3(0, 0, 5) + p.air.wind * t;
    EXPECT_LT((felt[i] - p.air.wind - field.velocity(at_it, t, p.air.wind)).norm(), 1e-9) << i;
    changed = std::max(changed, (felt[i] - felt[0]).norm());
  }
  test::printFigure("drifting_change", changed);
  EXPECT_GT(changed, field.scales().sigma.z());
}

// c(tau) is a correlation with the integral time it is built for: 1 at 0, 0 from 2D on
// (D = pi^2 T_L / 8), and int c = T_L; at every instant the field is a Dryden field, the
// frozen one at t = 0 (F_0), the same to the bit as a frozen field's.
TEST(Turbulence, TheAirMassCorrelationIntegratesToTheLagrangianTime) {
  const double t_l = 3.0, d = M_PI * M_PI * t_l / 8.0;
  EXPECT_DOUBLE_EQ(airMassCorrelation(0.0, t_l), 1.0);
  EXPECT_DOUBLE_EQ(airMassCorrelation(2.0 * d, t_l), 0.0);
  EXPECT_DOUBLE_EQ(airMassCorrelation(1e9, std::numeric_limits<double>::infinity()), 1.0);
  double integral = 0.0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) integral += airMassCorrelation((i + 0.5) * 2.0 * d / n, t_l);
  EXPECT_NEAR(integral * 2.0 * d / n, t_l, 1e-6);
  TurbulenceParams living = lightAtFiveMetres(3), frozen = living;
  frozen.frozen = true;
  const TurbulenceField a(living, 3), b(frozen, 3);
  for (double xi : {-40.0, 0.0, 12.5, 300.0}) {
    EXPECT_EQ(a.componentsAt(xi, 0.0), b.componentsAt(xi, 0.0)) << xi;
    EXPECT_EQ(b.componentsAt(xi, 50.0), b.componentsAt(xi, 0.0)) << xi;
    EXPECT_GT((a.componentsAt(xi, 50.0) - a.componentsAt(xi, 0.0)).norm(), 1e-3) << xi;
  }
}

// What a creature at rest in a 1 m/s wind feels is the model's spectrum in space seen through
// the decorrelation in time: drydenFeltSpectrum's quadrature is the closed form where it has
// one (frozen: Phi(omega / U) / U; carried by the air, at omega = 0: (2 / pi) sigma^2 T_L,
// int c being T_L), and integrates to sigma^2.
TEST(Turbulence, TheFeltSpectrumIsTheTransformOfTheCorrelationInSpaceAndTime) {
  const DrydenScales s = drydenScales(turbulenceLevelWind("light"), 5.0);
  const double t_l = lagrangianTime(s, 5.0);
  for (double omega : {0.05, 0.5, 3.0}) {
    EXPECT_DOUBLE_EQ(drydenFeltSpectrum(s, 2, omega, 1.0, std::numeric_limits<double>::infinity()),
                     drydenSpectrum(s, 2, omega));
  }
  EXPECT_NEAR(drydenFeltSpectrum(s, 0, 0.0, 0.0, t_l), 2.0 / M_PI * s.sigma[0] * s.sigma[0] * t_l,
              1e-9);
  for (int axis = 0; axis < 3; ++axis) {
    // On a log grid from 1e-4 to 1e3 rad/s (the tails beyond hold under 0.1 % of it).
    double variance = 0.0;
    const int n = 1200;
    const double step = std::log(1e7) / n;
    for (int i = 0; i < n; ++i) {
      const double omega = 1e-4 * std::exp((i + 0.5) * step);
      variance += drydenFeltSpectrum(s, axis, omega, 1.0, t_l) * omega * step;
    }
    test::printFigure(test::figureName("felt_variance_ratio_%c", "uvw"[axis]),
                      variance / (s.sigma[axis] * s.sigma[axis]));
    EXPECT_NEAR(variance / (s.sigma[axis] * s.sigma[axis]), 1.0, 0.005) << axis;
  }
}

TEST(Turbulence, GustRisesAsOneMinusCosineHoldsAndFalls) {
  DiscreteGust g;
  g.velocity = Vec3(0.0, 2.0, 0.0);
  g.start = 1.0;
  g.rise = 0.5;
  g.hold = 2.0;
  EXPECT_EQ(gustVelocity(g, 0.999), Vec3::Zero());
  EXPECT_NEAR(gustVelocity(g, 1.25).y(), 1.0, 1e-15);
  EXPECT_NEAR(gustVelocity(g, 1.125).y(), 1.0 - std::cos(M_PI / 4.0), 1e-15);
  EXPECT_EQ(gustVelocity(g, 1.5).y(), 2.0);
  EXPECT_EQ(gustVelocity(g, 3.4).y(), 2.0);
  EXPECT_NEAR(gustVelocity(g, 3.75).y(), 1.0, 1e-15);
  EXPECT_EQ(gustVelocity(g, 4.0), Vec3::Zero());
  g.hold = -1.0;
  EXPECT_EQ(gustVelocity(g, 1e6).y(), 2.0);
  EXPECT_NE(checkGust(DiscreteGust{Vec3(0, 0, 1), 0.0, 0.0, -1.0}).find("air/gust/rise"),
            std::string::npos);
  EXPECT_NE(
      checkTurbulence(TurbulenceParams{7.7, 1.0, false, false, 0}).find("air/turbulence/height"),
      std::string::npos);
}

// A free plate (10 g, 0.2 x 0.2 m, face-on to a 2 m/s gust along its normal, no gravity) is
// carried by the gust: once the gust holds, the air's drag 1/2 rho Cd A u^2 leaves a relative
// speed u(T) < (m + m_a) / (1/2 rho Cd A T) after T s, whatever it was (here 0.13 m/s after
// 5 s), and the plate never outruns the air.
TEST(Turbulence, AFreePlateIsCarriedByTheGust) {
  WorldParams p = test::openSky();
  p.gravity = Vec3::Zero();
  p.air.gust.velocity = Vec3(0.0, 0.0, 2.0);
  p.air.gust.start = 0.2;
  p.air.gust.rise = 0.5;
  World w(p);
  const CreatureModelPtr plate = test::loadUrdf("plate.urdf");
  w.spawn("plate", plate, at(0, 0, 5));
  const double mass = plate->totalMass();
  ASSERT_NEAR(mass, 0.01, 1e-12);
  const double k = 0.5 * p.air.density * p.air.drag_coefficient * 0.2 * 0.2;
  const double added = p.air.density * M_PI * 0.2 * 0.2 * 0.2 / 4.0;
  double fastest = 0.0;
  while (w.time() < 0.7 + 5.0 - 1e-9) {
    w.step();
    fastest = std::max(fastest, w.rootTwist("plate").linear.z());
  }
  const double relative = 2.0 - w.rootTwist("plate").linear.z();
  test::printFigure("relative_speed", relative);
  test::printFigure("bound", (mass + added) / (k * 5.0));
  test::printFigure("fastest", fastest);
  EXPECT_LT(relative, (mass + added) / (k * 5.0));
  EXPECT_GT(relative, 0.0);
  EXPECT_LE(fastest, 2.0);
  EXPECT_LT(std::abs(w.rootTwist("plate").linear.x()) + std::abs(w.rootTwist("plate").linear.y()),
            1e-9);
}

// Episodes draw a gyro bias per start from a stream of their own (the other draws stay as
// they were) and fly a realisation of the turbulence per start, the same on every run.
TEST(RealAir, EpisodesDrawAGyroBiasAndATurbulencePerStart) {
  EpisodeParams p;
  p.episodes = 6;
  p.max_wind = 1.0;
  const std::vector<EpisodeStart> plain = episodeStarts(p);
  p.gyro_bias = 0.02;
  const std::vector<EpisodeStart> biased = episodeStarts(p);
  double largest = 0.0;
  for (size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(plain[i].wind, biased[i].wind);
    EXPECT_EQ(plain[i].roll, biased[i].roll);
    EXPECT_EQ(plain[i].noise_seed, biased[i].noise_seed);
    EXPECT_EQ(plain[i].gyro_bias, Vec3::Zero());
    EXPECT_LE(biased[i].gyro_bias.norm(), 0.02);
    largest = std::max(largest, biased[i].gyro_bias.norm());
  }
  EXPECT_GT(largest, 0.005);

  const CreatureModelPtr unit = parseCreatureModel(makeCreatureUrdf(1, "afc"), "afc");
  const OpenLoopWingController open(StrokeCommand{60.0, 10.0, 1.2});
  p.duration = 2.0;
  p.world.air.turbulence.wind_at_6m = turbulenceLevelWind("moderate");
  auto height = [&](const EpisodeStart& s) {
    return runEpisode(unit, open, 0.02, p, s).final_height;
  };
  const double first = height(biased[0]), second = height(biased[1]);
  EXPECT_EQ(height(biased[0]), first);  // the same bits
  p.world.air.turbulence.wind_at_6m = 0.0;
  // The turbulence moved each flight, each by its own air.
  const double calm_first = height(biased[0]), calm_second = height(biased[1]);
  EXPECT_GT(std::abs(first - calm_first), 1e-3);
  EXPECT_GT(std::abs(second - calm_second), 1e-3);
  EXPECT_GT(std::abs((first - calm_first) - (second - calm_second)), 1e-3);
}

// The real-air impulses scale with the creature: afc_1 (23.0 g, 0.76 m across) gets a roll
// torque of 0.5 x weight x half-span = 0.043 N m and a push of 4 x its weight = 0.90 N (the
// hand-set 0.05 N m and 1 N of the robust preset); each unit of afc_4 the same push, and a
// torque four times as large.
TEST(RealAir, ImpulsesScaleWithTheCreature) {
  const CreatureModelPtr unit = parseCreatureModel(makeCreatureUrdf(1, "afc"), "afc");
  EXPECT_NEAR(unit->totalMass(), 0.023, 1e-9);
  EXPECT_NEAR(creatureSpan(*unit), 0.76, 0.005);
  const FlightCheckParams one = realAirParams(FlightCheckParams(), *unit);
  EXPECT_NEAR(one.gust_torque, 0.5 * 0.023 * 9.81 * 0.5 * creatureSpan(*unit), 1e-12);
  EXPECT_NEAR(one.gust_torque, 0.043, 0.001);
  EXPECT_NEAR(one.gust_force, 4.0 * 0.023 * 9.81, 1e-12);
  EXPECT_EQ(one.wind, 1.0);
  EXPECT_EQ(one.turbulence, turbulenceLevelWind("light"));
  EXPECT_EQ(one.noise, 0.05);
  EXPECT_EQ(one.gyro_bias, 0.02);
  EXPECT_EQ(one.altitude_noise, 0.05);
  const CreatureModelPtr four = parseCreatureModel(makeCreatureUrdf(4, "afc"), "afc4");
  const FlightCheckParams chain = realAirParams(FlightCheckParams(), *four);
  EXPECT_NEAR(chain.gust_force, one.gust_force, 1e-9);
  EXPECT_NEAR(chain.gust_torque / one.gust_torque, 4.0 * creatureSpan(*four) / creatureSpan(*unit),
              1e-9);
}

}  // namespace
}  // namespace flapsim
