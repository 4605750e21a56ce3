// Nice ticks and min/max decimation (see plot_scale.hpp).
#include "redpost/report/plot_scale.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace redpost::report {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 10^k for integer k; pow is exact enough here and the same on every run.
double pow10i(int k) {
  return std::pow(10.0, k);
}

}  // namespace

double nice_step(double span, int target_intervals) {
  if (!(span > 0.0) || !std::isfinite(span)) {
    return 1.0;
  }
  const double raw = span / std::max(1, target_intervals);
  const int k = static_cast<int>(std::floor(std::log10(raw)));
  const double f = raw / pow10i(k);  // in [1, 10) up to rounding
  // The small tolerance keeps 0.30000000000000004 / 0.1 from stepping up to the next size.
  constexpr double kTol = 1e-9;
  if (f <= 1.0 + kTol)
    return pow10i(k);
  if (f <= 2.0 + kTol)
    return 2.0 * pow10i(k);
  if (f <= 5.0 + kTol)
    return 5.0 * pow10i(k);
  return pow10i(k + 1);
}

LinearTicks nice_linear_ticks(double data_min, double data_max, int target_intervals, bool expand) {
  if (!std::isfinite(data_min) || !std::isfinite(data_max)) {
    data_min = 0.0;
    data_max = 1.0;
  }
  if (data_min > data_max) {
    std::swap(data_min, data_max);
  }
  if (data_max - data_min <= 1e-12 * std::max(std::abs(data_min), std::abs(data_max))) {
    // A constant series: show it in the middle of a small range around its value.
    const double pad = data_min == 0.0 ? 1.0 : 0.1 * std::abs(data_min);
    data_min -= pad;
    data_max += pad;
  }
  LinearTicks t;
  t.step = nice_step(data_max - data_min, target_intervals);
  if (expand) {
    t.lo = std::floor(data_min / t.step + 1e-9) * t.step;
    t.hi = std::ceil(data_max / t.step - 1e-9) * t.step;
  } else {
    t.lo = data_min;
    t.hi = data_max;
  }
  const double k0 = std::ceil(t.lo / t.step - 1e-9);
  const double k1 = std::floor(t.hi / t.step + 1e-9);
  for (double k = k0; k <= k1; k += 1.0) {
    // k * step, not a running sum, so that rounding does not accumulate along the axis.
    const double v = k * t.step;
    t.ticks.push_back(k == 0.0 ? 0.0 : v);
  }
  return t;
}

LogTicks nice_log_ticks(double data_min, double data_max, int target_intervals) {
  if (!(data_min > 0.0) || !(data_max > 0.0) || !std::isfinite(data_min) ||
      !std::isfinite(data_max)) {
    data_min = 1.0;
    data_max = 10.0;
  }
  if (data_min > data_max) {
    std::swap(data_min, data_max);
  }
  int d0 = static_cast<int>(std::floor(std::log10(data_min) + 1e-9));
  int d1 = static_cast<int>(std::ceil(std::log10(data_max) - 1e-9));
  if (d1 <= d0) {
    d1 = d0 + 1;
  }
  const int decades = d1 - d0;
  const int every =
      std::max(1, (decades + std::max(1, target_intervals) - 1) / std::max(1, target_intervals));
  // Align the range to whole groups of decades so that both ends carry a label.
  d0 = static_cast<int>(std::floor(static_cast<double>(d0) / every)) * every;
  d1 = static_cast<int>(std::ceil(static_cast<double>(d1) / every)) * every;
  LogTicks t;
  t.lo = pow10i(d0);
  t.hi = pow10i(d1);
  for (int d = d0; d <= d1; d += every) {
    t.ticks.push_back(pow10i(d));
    if (d == d1 || every > 1) {
      continue;
    }
    for (int m = 2; m <= 9; ++m) {
      if (decades <= 2 && (m == 2 || m == 5)) {
        t.ticks.push_back(m * pow10i(d));
      } else {
        t.minor.push_back(m * pow10i(d));
      }
    }
  }
  std::sort(t.ticks.begin(), t.ticks.end());
  return t;
}

std::string format_tick(double value, double step) {
  if (!std::isfinite(value)) {
    return "NaN";
  }
  if (!(step > 0.0) || !std::isfinite(step)) {
    step = std::abs(value) > 0.0 ? std::abs(value) : 1.0;
  }
  if (std::abs(value) < 1e-9 * step) {
    value = 0.0;  // never "-0" or "1.2e-17" for the zero tick
  }
  const int step_exp = static_cast<int>(std::floor(std::log10(step) + 1e-9));
  // Decimals: the fewest that write every multiple of the step exactly (2 for 0.25, 0 for 200).
  int decimals = 0;
  for (double scaled = step; decimals < 12; ++decimals, scaled *= 10.0) {
    if (std::abs(scaled - std::round(scaled)) <= 1e-6 * scaled)
      break;
  }
  if (std::abs(value) >= 1e7 || step_exp < -5) {
    if (value == 0.0) {
      return "0";
    }
    const int value_exp = static_cast<int>(std::floor(std::log10(std::abs(value))));
    const int digits = std::clamp(value_exp - step_exp + std::max(0, decimals + step_exp), 0, 12);
    return fmt::format("{:.{}e}", value, digits);
  }
  return fmt::format("{:.{}f}", value, decimals);
}

std::string format_log_tick(double value) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    return "NaN";
  }
  const int e = static_cast<int>(std::floor(std::log10(value) + 1e-9));
  if (e >= -3 && e <= 5) {
    return format_tick(value, pow10i(e));
  }
  const double mantissa = std::round(value / pow10i(e) * 1e6) / 1e6;
  if (mantissa == 1.0) {
    return fmt::format("1e{}", e);
  }
  return fmt::format("{}e{}", mantissa, e);
}

// --- MinMaxDecimator ------------------------------------------------------------------------

MinMaxDecimator::MinMaxDecimator(int max_buckets)
    : max_buckets_(static_cast<std::size_t>(std::max(1, max_buckets))) {
  buckets_.reserve(2 * max_buckets_);
}

void MinMaxDecimator::add(Bucket& b, double x, double y, std::size_t i) {
  if (std::isnan(y) || std::isnan(x)) {
    if (!b.nan) {
      b.nan = true;
      b.i_nan = i;
    }
    return;
  }
  if (!b.finite) {
    b.finite = true;
    b.x_min = b.x_max = x;
    b.y_min = b.y_max = y;
    b.i_min = b.i_max = i;
    return;
  }
  // Strict comparisons: of equal extremes the first one is kept.
  if (y < b.y_min) {
    b.y_min = y;
    b.x_min = x;
    b.i_min = i;
  }
  if (y > b.y_max) {
    b.y_max = y;
    b.x_max = x;
    b.i_max = i;
  }
}

MinMaxDecimator::Bucket MinMaxDecimator::merged(const Bucket& a, const Bucket& b) {
  // a holds earlier samples than b.
  Bucket m = a;
  if (b.finite) {
    if (!m.finite) {
      m.finite = true;
      m.x_min = b.x_min, m.y_min = b.y_min, m.i_min = b.i_min;
      m.x_max = b.x_max, m.y_max = b.y_max, m.i_max = b.i_max;
    } else {
      if (b.y_min < m.y_min) {
        m.x_min = b.x_min, m.y_min = b.y_min, m.i_min = b.i_min;
      }
      if (b.y_max > m.y_max) {
        m.x_max = b.x_max, m.y_max = b.y_max, m.i_max = b.i_max;
      }
    }
  }
  if (b.nan && !m.nan) {
    m.nan = true;
    m.i_nan = b.i_nan;
  }
  return m;
}

void MinMaxDecimator::halve() {
  const std::size_t n = buckets_.size();
  std::size_t out = 0;
  for (std::size_t k = 0; k + 1 < n; k += 2) {
    buckets_[out++] = merged(buckets_[k], buckets_[k + 1]);
  }
  if (n % 2 == 1) {
    buckets_[out++] = buckets_[n - 1];
  }
  buckets_.resize(out);
  in_last_ = (n % 2 == 1) ? in_last_ : in_last_ + width_;
  width_ *= 2;
}

void MinMaxDecimator::push(double y) {
  push(static_cast<double>(samples_), y);
}

void MinMaxDecimator::push(double x, double y) {
  if (buckets_.empty() || in_last_ == width_) {
    if (buckets_.size() == 2 * max_buckets_) {
      halve();  // all 2N buckets are full: N buckets of twice the width, all full
    }
    if (buckets_.empty() || in_last_ == width_) {
      buckets_.push_back(Bucket{});
      in_last_ = 0;
    }
  }
  add(buckets_.back(), x, y, samples_);
  ++in_last_;
  ++samples_;
}

std::size_t MinMaxDecimator::bucket_width() const {
  return buckets_.size() > max_buckets_ ? 2 * width_ : width_;
}

XYSeries MinMaxDecimator::result() const {
  std::vector<Bucket> b = buckets_;
  if (b.size() > max_buckets_) {
    // Between N and 2N buckets: one more pairwise merge gives at most N.
    std::size_t out = 0;
    for (std::size_t k = 0; k < b.size(); k += 2) {
      b[out++] = k + 1 < b.size() ? merged(b[k], b[k + 1]) : b[k];
    }
    b.resize(out);
  }
  XYSeries s;
  s.x.reserve(3 * b.size());
  s.y.reserve(3 * b.size());
  for (const Bucket& bk : b) {
    // Up to three events per bucket, emitted in the order they were pushed.
    std::pair<std::size_t, int> ev[3];
    int n = 0;
    if (bk.finite) {
      ev[n++] = {bk.i_min, 0};
      if (bk.i_max != bk.i_min) {
        ev[n++] = {bk.i_max, 1};
      }
    }
    if (bk.nan) {
      ev[n++] = {bk.i_nan, 2};
    }
    std::sort(ev, ev + n);
    for (int k = 0; k < n; ++k) {
      switch (ev[k].second) {
        case 0:
          s.x.push_back(bk.x_min), s.y.push_back(bk.y_min);
          break;
        case 1:
          s.x.push_back(bk.x_max), s.y.push_back(bk.y_max);
          break;
        default:
          s.x.push_back(kNaN), s.y.push_back(kNaN);
          break;
      }
    }
  }
  return s;
}

XYSeries downsample_min_max(const double* x, const double* y, std::size_t n, int max_buckets) {
  MinMaxDecimator d(max_buckets);
  for (std::size_t i = 0; i < n; ++i) {
    d.push(x != nullptr ? x[i] : static_cast<double>(i), y[i]);
  }
  return d.result();
}

}  // namespace redpost::report
