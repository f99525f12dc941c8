// Power spectral density of a sampled signal (Welch's method), to check a generated signal
// against the spectrum it was made to have (the turbulence's). No state, no clock.
#pragma once

#include <vector>

namespace flapsim {

/// A one-sided spectrum: density[k] at frequency[k] (rad per unit of the sample spacing's
/// unit), integrating to the signal's variance over [0, pi / spacing].
struct Spectrum {
  std::vector<double> frequency;
  std::vector<double> density;
};

/// Welch's estimate: the samples (spacing apart, in time or space) cut into segments of
/// `segment` samples (a power of two, at most the sample count) overlapping by half, each
/// less its mean and Hann-windowed, their periodograms averaged. Throws InputError for a
/// segment that is not a power of two >= 8 or longer than the samples.
Spectrum welchSpectrum(const std::vector<double>& samples, double spacing, int segment);

/// The mean density over frequencies in [low, high) (0 if none).
double bandDensity(const Spectrum& spectrum, double low, double high);

}  // namespace flapsim
