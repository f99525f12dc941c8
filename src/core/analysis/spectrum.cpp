#include "flapsim/spectrum.h"

#include <cmath>
#include <complex>
#include <string>
#include <unsupported/Eigen/FFT>

#include "flapsim/types.h"

namespace flapsim {

Spectrum welchSpectrum(const std::vector<double>& samples, double spacing, int segment) {
  const int n = static_cast<int>(samples.size());
  if (segment < 8 || (segment & (segment - 1)) != 0 || segment > n) {
    throw InputError("spectrum segment must be a power of two in [8, " + std::to_string(n) +
                     "], got " + std::to_string(segment));
  }
  std::vector<double> window(segment);
  double window_power = 0.0;
  for (int i = 0; i < segment; ++i) {
    window[i] = 0.5 - 0.5 * std::cos(2.0 * M_PI * i / segment);
    window_power += window[i] * window[i];
  }
  Spectrum out;
  const int bins = segment / 2;
  out.frequency.resize(bins + 1);
  out.density.assign(bins + 1, 0.0);
  for (int k = 0; k <= bins; ++k) out.frequency[k] = 2.0 * M_PI * k / (segment * spacing);
  Eigen::FFT<double> fft;
  std::vector<double> piece(segment);
  std::vector<std::complex<double>> transform;
  int count = 0;
  for (int first = 0; first + segment <= n; first += segment / 2, ++count) {
    double mean = 0.0;
    for (int i = 0; i < segment; ++i) mean += samples[first + i];
    mean /= segment;
    for (int i = 0; i < segment; ++i) piece[i] = (samples[first + i] - mean) * window[i];
    fft.fwd(transform, piece);
    for (int k = 0; k <= bins; ++k) out.density[k] += std::norm(transform[k]);
  }
  // |X_k|^2 spacing / (2 pi sum w^2) per rad/unit, doubled for the negative frequencies
  // except at 0 and Nyquist.
  const double scale = spacing / (2.0 * M_PI * window_power * count);
  for (int k = 0; k <= bins; ++k) out.density[k] *= (k == 0 || k == bins ? 1.0 : 2.0) * scale;
  return out;
}

double bandDensity(const Spectrum& s, double low, double high) {
  double sum = 0.0;
  int count = 0;
  for (size_t k = 0; k < s.frequency.size(); ++k) {
    if (s.frequency[k] >= low && s.frequency[k] < high) {
      sum += s.density[k];
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

}  // namespace flapsim
