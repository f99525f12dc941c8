#include "flapsim/turbulence.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <functional>
#include <iterator>
#include <limits>
#include <sstream>

#include "flapsim/ga.h"

namespace flapsim {

double turbulenceLevelWind(const std::string& level) {
  const double knot = 1852.0 / 3600.0;  // m/s
  if (level == "none") return 0.0;
  if (level == "light") return 15.0 * knot;
  if (level == "moderate") return 30.0 * knot;
  if (level == "severe") return 45.0 * knot;
  throw InputError("turbulence level '" + level + "' is not one of none, light, moderate, severe");
}

double turbulenceWindFromText(const std::string& text) {
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  if (!text.empty() && end == text.c_str() + text.size()) {
    if (!(number >= 0.0 && number <= kMaxTurbulenceWind)) {
      throw InputError("turbulence wind at 6 m '" + text + "' is not in [0, 100] m/s");
    }
    return number;
  }
  try {
    return turbulenceLevelWind(text);
  } catch (const InputError&) {
    throw InputError("turbulence '" + text +
                     "' is not one of none, light, moderate, severe nor a wind at 6 m in m/s");
  }
}

double turbulenceWindFromFlag(const std::string& flag, const std::string& text) {
  try {
    return turbulenceWindFromText(text);
  } catch (const InputError& e) {
    throw InputError(flag + ": " + e.what());
  }
}

DrydenScales drydenScales(double wind_at_6m, double height) {
  const double feet = height / 0.3048;
  const double denominator = 0.177 + 0.000823 * feet;
  DrydenScales s;
  const double sigma_w = 0.1 * wind_at_6m;
  const double sigma_uv = sigma_w / std::pow(denominator, 0.4);
  s.sigma = Vec3(sigma_uv, sigma_uv, sigma_w);
  const double l_uv = height / std::pow(denominator, 1.2);
  s.length = Vec3(l_uv, l_uv, height);
  return s;
}

double drydenSpectrum(const DrydenScales& s, int axis, double omega) {
  const double sigma2 = s.sigma[axis] * s.sigma[axis], l = s.length[axis];
  const double x2 = l * omega * l * omega;
  if (axis == 0) return sigma2 * 2.0 * l / M_PI / (1.0 + x2);
  return sigma2 * l / M_PI * (1.0 + 3.0 * x2) / ((1.0 + x2) * (1.0 + x2));
}

double drydenVariance(const DrydenScales& s, int axis, double omega) {
  const double sigma2 = s.sigma[axis] * s.sigma[axis];
  if (std::isinf(omega)) return sigma2;
  const double x = s.length[axis] * omega;
  if (axis == 0) return sigma2 * 2.0 / M_PI * std::atan(x);
  return sigma2 / M_PI * (2.0 * std::atan(x) - x / (1.0 + x * x));
}

double lagrangianTime(const DrydenScales& s, double height) {
  if (!(s.sigma.z() > 0.0)) return std::numeric_limits<double>::infinity();
  return 0.5 * height / s.sigma.z();
}

namespace {
// D, the time between the births of the field's realisations, for an integral time T_L.
double renewalTime(double lagrangian_time) { return M_PI * M_PI * lagrangian_time / 8.0; }

// Of the entries of `map` from `first` on, erases the one whose key is farthest from `key`
// (the first or the last: the keys are sorted); the cache makes it again, the same, if needed.
template <class Map>
void eraseFarthest(Map& map, typename Map::iterator first, std::int64_t key) {
  auto last = std::prev(map.end());
  map.erase(std::abs(first->first - key) > std::abs(last->first - key) ? first : last);
}
}  // namespace

double airMassCorrelation(double tau, double lagrangian_time) {
  if (std::isinf(lagrangian_time)) return 1.0;
  const double d = renewalTime(lagrangian_time), t = std::abs(tau);
  if (t >= 2.0 * d) return 0.0;
  const double a = M_PI / (2.0 * d);
  return ((2.0 * d - t) * std::cos(a * t) + std::sin(a * t) / a) / (2.0 * d);
}

double drydenFeltSpectrum(const DrydenScales& s, int axis, double omega, double speed,
                          double lagrangian_time) {
  const double sigma2 = s.sigma[axis] * s.sigma[axis], l = s.length[axis];
  if (std::isinf(lagrangian_time)) {
    return speed > 0.0 ? drydenSpectrum(s, axis, omega / speed) / speed : 0.0;
  }
  // Simpson's rule over the correlation's support [0, 2D], fine against its wiggles and omega.
  const double span = 2.0 * renewalTime(lagrangian_time);
  const int n = 2 * std::max(2000, static_cast<int>(std::ceil(4.0 * omega * span)));
  const double h = span / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double tau = i * h, r = speed * tau / l;
    const double space = axis == 0 ? std::exp(-r) : (1.0 - 0.5 * r) * std::exp(-r);
    const double f =
        sigma2 * space * airMassCorrelation(tau, lagrangian_time) * std::cos(omega * tau);
    sum += (i == 0 || i == n ? 1.0 : i % 2 == 1 ? 4.0 : 2.0) * f;
  }
  return 2.0 / M_PI * sum * h / 3.0;
}

std::string checkTurbulence(const TurbulenceParams& p) {
  std::ostringstream out;
  if (!(p.wind_at_6m >= 0.0 && p.wind_at_6m <= kMaxTurbulenceWind)) {
    out << "air/turbulence/wind_at_6m must be in [0, " << kMaxTurbulenceWind << "] m/s, got "
        << p.wind_at_6m;
  } else if (!(p.height >= kMinTurbulenceHeight && p.height <= kMaxTurbulenceHeight)) {
    out << "air/turbulence/height must be in [" << kMinTurbulenceHeight << ", "
        << kMaxTurbulenceHeight << "] m (the model's low-altitude range, 10-1000 ft), got "
        << p.height;
  }
  return out.str();
}

std::string checkGust(const DiscreteGust& g) {
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(g.velocity[i]) <= kMaxGustSpeed)) {
      return "air/gust/velocity must be finite, each component within +-1000 m/s";
    }
  }
  if (!(std::isfinite(g.start) && g.start >= 0.0)) return "air/gust/start must be >= 0 s";
  if (!(std::isfinite(g.rise) && g.rise > 0.0 && g.rise <= 1e6)) {
    return "air/gust/rise must be in (0, 1e6] s";
  }
  if (!(std::isfinite(g.hold) && g.hold <= 1e9)) {
    return "air/gust/hold must be finite and at most 1e9 s (< 0: the gust stays)";
  }
  return "";
}

TurbulenceField::TurbulenceField(const TurbulenceParams& params, std::uint64_t realisation_seed) {
  const std::string err = checkTurbulence(params);
  if (!err.empty()) throw InputError(err);
  if (params.wind_at_6m == 0.0) return;
  scales_ = drydenScales(params.wind_at_6m, params.height);
  spacing_ = scales_.length.minCoeff() / 500.0;
  lagrangian_time_ = params.frozen ? std::numeric_limits<double>::infinity()
                                   : flapsim::lagrangianTime(scales_, params.height);
  renewal_ = renewalTime(lagrangian_time_);
  seed_ = realisation_seed;
  const double lowest = 0.01 / scales_.length.maxCoeff();
  const double highest = 100.0 / scales_.length.minCoeff();
  const int n = kTurbulenceModes;
  // Band edges: 0, then n - 1 log-spaced edges from lowest to highest, then infinity.
  const double ratio = std::pow(highest / lowest, 1.0 / (n - 2));
  auto edge = [&](int j) {
    if (j == 0) return 0.0;
    if (j == n) return std::numeric_limits<double>::infinity();
    return lowest * std::pow(ratio, j - 1);
  };
  Rng rng(realisation_seed);
  omega_.resize(n);
  amplitude_.resize(n);
  Realisation first;
  first.cos_amplitude.resize(n);
  first.sin_amplitude.resize(n);
  for (int k = 0; k < n; ++k) {
    // The mode's frequency, log-uniform within its band (the open bands as wide as the rest).
    const double lo = k == 0 ? lowest / ratio : edge(k);
    omega_[k] = lo * std::pow(ratio, rng.uniform());
    for (int axis = 0; axis < 3; ++axis) {
      const double variance =
          drydenVariance(scales_, axis, edge(k + 1)) - drydenVariance(scales_, axis, edge(k));
      amplitude_[k][axis] = std::sqrt(2.0 * std::max(variance, 0.0));
      setPhase(first, k, axis, 2.0 * M_PI * rng.uniform());
    }
  }
  realisations_.emplace(0, std::move(first));
}

void TurbulenceField::setPhase(Realisation& r, size_t k, int axis, double phase) const {
  r.cos_amplitude[k][axis] = amplitude_[k][axis] * std::cos(phase);
  r.sin_amplitude[k][axis] = -amplitude_[k][axis] * std::sin(phase);
}

TurbulenceField::Realisation& TurbulenceField::realisation(std::int64_t m) const {
  auto found = realisations_.find(m);
  if (found != realisations_.end()) return found->second;
  if (realisations_.size() >= kRealisationsKept) {  // F_0 is kept
    eraseFarthest(realisations_, std::next(realisations_.begin()), m);
  }
  Rng rng(mixSeed(seed_, 0x6c697665ULL, static_cast<std::uint64_t>(m)));  // "live"
  Realisation r;
  r.chunk = kLivingChunk;
  r.cos_amplitude.resize(omega_.size());
  r.sin_amplitude.resize(omega_.size());
  for (size_t k = 0; k < omega_.size(); ++k) {
    for (int axis = 0; axis < 3; ++axis) setPhase(r, k, axis, 2.0 * M_PI * rng.uniform());
  }
  return realisations_.emplace(m, std::move(r)).first->second;
}

const std::vector<Vec3>& TurbulenceField::chunk(Realisation& r, std::int64_t index) const {
  auto found = r.chunks.find(index);
  if (found == r.chunks.end()) {
    if (r.chunks.size() >= kChunksKept) eraseFarthest(r.chunks, r.chunks.begin(), index);
    // Each mode's angle at the chunk's first point, then turned point by point.
    std::vector<Vec3> values(r.chunk + 1, Vec3::Zero());
    const double first = static_cast<double>(index) * r.chunk * spacing_;
    for (size_t k = 0; k < omega_.size(); ++k) {
      const std::complex<double> turn = std::polar(1.0, omega_[k] * spacing_);
      std::complex<double> phasor = std::polar(1.0, omega_[k] * first);
      for (int j = 0; j <= r.chunk; ++j, phasor *= turn) {
        values[j] += r.cos_amplitude[k] * phasor.real() + r.sin_amplitude[k] * phasor.imag();
      }
    }
    found = r.chunks.emplace(index, std::move(values)).first;
  }
  return found->second;
}

Vec3 TurbulenceField::realisationAt(Realisation& r, double xi) const {
  const double position = xi / spacing_;
  const double cell = std::floor(position);
  const auto point = static_cast<std::int64_t>(cell);
  const std::int64_t index = point >= 0 ? point / r.chunk : -((-point - 1) / r.chunk) - 1;
  const int j = static_cast<int>(point - index * r.chunk);
  const std::vector<Vec3>& values = chunk(r, index);
  const double t = position - cell;
  return values[j] + t * (values[j + 1] - values[j]);
}

Vec3 TurbulenceField::componentsAt(double xi, double time) const {
  if (!active()) return Vec3::Zero();
  if (std::isinf(renewal_)) return realisationAt(realisation(0), xi);  // frozen
  const double age = std::max(time, 0.0) / renewal_;
  const double born = std::floor(age);
  const auto m = static_cast<std::int64_t>(born);
  const double u = age - born;
  const Vec3 older = realisationAt(realisation(m), xi);
  if (u == 0.0) return older;
  return std::cos(0.5 * M_PI * u) * older +
         std::sin(0.5 * M_PI * u) * realisationAt(realisation(m + 1), xi);
}

Vec3 TurbulenceField::velocity(const Vec3& position, double time, const Vec3& wind) const {
  if (!active()) return Vec3::Zero();
  const Vec3 horizontal(wind.x(), wind.y(), 0.0);
  const double speed = horizontal.norm();
  const Vec3 along = speed > 0.0 ? Vec3(horizontal / speed) : Vec3::UnitX();
  const Vec3 across = Vec3::UnitZ().cross(along);
  const Vec3 c = componentsAt(along.dot(position) - speed * time, time);
  return c.x() * along + c.y() * across + c.z() * Vec3::UnitZ();
}

std::uint64_t turbulenceSeed(const TurbulenceParams& params, const std::string& creature) {
  if (!params.per_creature) return mixSeed(params.seed, 0x7475726275ULL);
  std::uint64_t h = 1469598103934665603ULL;  // FNV-1a of the name
  for (unsigned char c : creature) h = (h ^ c) * 1099511628211ULL;
  return mixSeed(params.seed, 0x7475726275ULL, h);
}

Vec3 gustVelocity(const DiscreteGust& g, double time) {
  if (g.velocity.isZero(0.0) || time < g.start) return Vec3::Zero();
  const double tau = time - g.start;
  if (tau < g.rise) return g.velocity * 0.5 * (1.0 - std::cos(M_PI * tau / g.rise));
  if (g.hold < 0.0 || tau < g.rise + g.hold) return g.velocity;
  const double fall = tau - g.rise - g.hold;
  if (fall < g.rise) return g.velocity * 0.5 * (1.0 + std::cos(M_PI * fall / g.rise));
  return Vec3::Zero();
}

}  // namespace flapsim
