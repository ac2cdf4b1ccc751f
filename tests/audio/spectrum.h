// Test-only spectrum toolkit: radix-2 FFT, Hann-windowed Welch power spectra, band energy, spectral centroid, and peak frequency by interpolation and refinement.
#pragma once

#include <algorithm>
#include <cassert>
#include <cmath>
#include <complex>
#include <numbers>
#include <span>
#include <vector>

namespace dentsim::test {

// In-place iterative radix-2 FFT (decimation in time); a.size() must be a power of two.
inline void fft(std::vector<std::complex<double>>& a) {
  const size_t n = a.size();
  assert(n > 0 && (n & (n - 1)) == 0);
  for (size_t i = 1, j = 0; i < n; ++i) {  // bit-reversed order
    size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (size_t len = 2; len <= n; len <<= 1) {
    const double angle = -2.0 * std::numbers::pi / double(len);
    const std::complex<double> step(std::cos(angle), std::sin(angle));
    for (size_t start = 0; start < n; start += len) {
      std::complex<double> w(1.0, 0.0);
      for (size_t k = 0; k < len / 2; ++k) {
        const std::complex<double> even = a[start + k], odd = a[start + k + len / 2] * w;
        a[start + k] = even + odd;
        a[start + k + len / 2] = even - odd;
        w *= step;
      }
    }
  }
}

inline double hann(size_t i, size_t n) {
  return 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * double(i) / double(n));
}

struct PowerSpectrum {
  double bin_hz = 0.0;         // spacing of the bins [Hz]
  std::vector<double> power;   // bins 0 .. nfft / 2, averaged over segments (arbitrary but common units)
};

// Welch's method: Hann-windowed segments of nfft samples, half overlapping, power averaged.
inline PowerSpectrum welch(std::span<const float> x, double fs, size_t nfft = 4096) {
  assert(x.size() >= nfft);
  PowerSpectrum out;
  out.bin_hz = fs / double(nfft);
  out.power.assign(nfft / 2 + 1, 0.0);
  std::vector<std::complex<double>> buf(nfft);
  int segments = 0;
  for (size_t start = 0; start + nfft <= x.size(); start += nfft / 2, ++segments) {
    for (size_t i = 0; i < nfft; ++i) buf[i] = double(x[start + i]) * hann(i, nfft);
    fft(buf);
    for (size_t k = 0; k <= nfft / 2; ++k) out.power[k] += std::norm(buf[k]);
  }
  for (double& p : out.power) p /= segments;
  return out;
}

// Power in [lo_hz, hi_hz).
inline double bandEnergy(const PowerSpectrum& s, double lo_hz, double hi_hz) {
  double sum = 0.0;
  for (size_t k = 0; k < s.power.size(); ++k) {
    const double f = double(k) * s.bin_hz;
    if (f >= lo_hz && f < hi_hz) sum += s.power[k];
  }
  return sum;
}

// The power-weighted mean frequency [Hz].
inline double spectralCentroid(const PowerSpectrum& s) {
  double weighted = 0.0, total = 0.0;
  for (size_t k = 0; k < s.power.size(); ++k) {
    weighted += double(k) * s.bin_hz * s.power[k];
    total += s.power[k];
  }
  return total > 0 ? weighted / total : 0.0;
}

// |X(f)|^2 of the Hann-windowed block at any frequency (the DTFT), for refining a peak between bins.
inline double windowedPowerAt(std::span<const float> x, double fs, double f) {
  const double angle = -2.0 * std::numbers::pi * f / fs;
  const std::complex<double> step(std::cos(angle), std::sin(angle));
  std::complex<double> phasor(1.0, 0.0), sum(0.0, 0.0);
  for (size_t i = 0; i < x.size(); ++i) {
    sum += double(x[i]) * hann(i, x.size()) * phasor;
    phasor *= step;
    if ((i & 1023) == 1023) phasor /= std::abs(phasor);  // keep the rotation on the unit circle
  }
  return std::norm(sum);
}

// The frequency of the strongest spectral peak within [lo_hz, hi_hz] [Hz]: the largest bin of a
// Hann-windowed, 4x zero-padded FFT, a parabola through the log power of it and its neighbours,
// then a golden-section search of the windowed DTFT within half a bin of that estimate.
inline double peakFrequency(std::span<const float> x, double fs, double lo_hz, double hi_hz) {
  size_t nfft = 1;
  while (nfft < 4 * x.size()) nfft <<= 1;
  std::vector<std::complex<double>> buf(nfft, {0.0, 0.0});
  for (size_t i = 0; i < x.size(); ++i) buf[i] = double(x[i]) * hann(i, x.size());
  fft(buf);
  const double bin = fs / double(nfft);
  size_t best = 0;
  double best_power = -1.0;
  for (size_t k = 1; k + 1 < nfft / 2; ++k) {
    const double f = double(k) * bin;
    if (f < lo_hz || f > hi_hz) continue;
    if (std::norm(buf[k]) > best_power) {
      best_power = std::norm(buf[k]);
      best = k;
    }
  }
  if (best == 0) return 0.0;
  const double l = std::log(std::norm(buf[best - 1]) + 1e-300), c = std::log(std::norm(buf[best]) + 1e-300),
               r = std::log(std::norm(buf[best + 1]) + 1e-300);
  const double denom = l - 2.0 * c + r;
  const double offset = denom < 0 ? std::clamp(0.5 * (l - r) / denom, -0.5, 0.5) : 0.0;
  double a = (double(best) + offset - 0.5) * bin, b = (double(best) + offset + 0.5) * bin;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double p1 = windowedPowerAt(x, fs, x1), p2 = windowedPowerAt(x, fs, x2);
  for (int it = 0; it < 30; ++it) {
    if (p1 > p2) {
      b = x2;
      x2 = x1;
      p2 = p1;
      x1 = b - g * (b - a);
      p1 = windowedPowerAt(x, fs, x1);
    } else {
      a = x1;
      x1 = x2;
      p1 = p2;
      x2 = a + g * (b - a);
      p2 = windowedPowerAt(x, fs, x2);
    }
  }
  return 0.5 * (a + b);
}

inline double rms(std::span<const float> x) {
  double sum = 0.0;
  for (float v : x) sum += double(v) * double(v);
  return x.empty() ? 0.0 : std::sqrt(sum / double(x.size()));
}

// The largest |x[n+1] - x[n]|: a click shows as a step far above the signal's own.
inline double maxStep(std::span<const float> x) {
  double m = 0.0;
  for (size_t i = 1; i < x.size(); ++i) m = std::max(m, std::abs(double(x[i]) - double(x[i - 1])));
  return m;
}

}  // namespace dentsim::test
