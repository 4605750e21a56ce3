// Plot scaling for the report writer (issue 9): "nice" axis ticks and min/max downsampling.
//
// Plain numbers in, plain numbers out; no drawing here, so that the rules the plots rely on
// (ticks are 1, 2 or 5 x 10^k; a downsampled series keeps every bucket's extremes) can be
// tested on their own.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace redpost::report {

// The smallest step of the form 1, 2 or 5 x 10^k that divides span into at most
// target_intervals intervals. span <= 0 or not finite gives 1.
double nice_step(double span, int target_intervals);

// A linear axis: its range and the ticks on it (multiples of step within [lo, hi]).
struct LinearTicks {
  double lo = 0.0;
  double hi = 1.0;
  double step = 0.1;
  std::vector<double> ticks;
};

// Ticks for data in [data_min, data_max], about target_intervals of them. With expand the
// range grows to the enclosing multiples of the step (the usual plot axis); without, the range
// is the data range and the ticks are the multiples of the step inside it. An empty or
// degenerate range is widened around its value; non-finite input gives [0, 1].
LinearTicks nice_linear_ticks(double data_min, double data_max, int target_intervals = 5,
                              bool expand = true);

// A base-10 logarithmic axis over whole decades. ticks are the labelled values: powers of ten
// (every decade_step-th decade for wide ranges), plus 2 and 5 x 10^k when the range spans at
// most two decades. minor are the unlabelled 2..9 x 10^k marks (empty for wide ranges).
struct LogTicks {
  double lo = 1.0;
  double hi = 10.0;
  std::vector<double> ticks;
  std::vector<double> minor;
};

// data_min and data_max must be positive (non-positive or non-finite input gives [1, 10]).
LogTicks nice_log_ticks(double data_min, double data_max, int target_intervals = 5);

// A tick label with as many decimals as the step needs ("0.25", "1200", "-3"), never "-0",
// scientific ("1.5e+07") for very large or very small magnitudes. Locale-independent (fmt).
std::string format_tick(double value, double step);

// A log-axis tick label: "0.01", "200", "1e-06" style for far decades. Locale-independent.
std::string format_log_tick(double value);

// A series after downsampling: y is NaN where the line must break (a gap in the data).
struct XYSeries {
  std::vector<double> x;
  std::vector<double> y;
};

// Streaming min/max decimation into at most max_buckets buckets of equal sample count.
//
// Samples are pushed one at a time, so a long run (a million poses) can be reduced while it
// is computed, without knowing its length or keeping it. Each bucket remembers its smallest
// and largest finite y (with their x) and whether it held a NaN; the result gives, per bucket
// and in the order they were pushed, the minimum, the maximum and a NaN break. So a one-sample
// peak is never lost, however long the series. Buckets start one sample wide and double in
// width (adjacent pairs merged) whenever 2 * max_buckets are full; a series of at most
// 2 * max_buckets samples therefore comes back unchanged. Memory is O(max_buckets), a push is
// O(1) amortised.
class MinMaxDecimator {
 public:
  explicit MinMaxDecimator(int max_buckets = 2000);

  void push(double y);  // x is the sample index 0, 1, 2, ...
  void push(double x, double y);

  std::size_t sample_count() const { return samples_; }
  // Samples per bucket of the result (1 when nothing was merged).
  std::size_t bucket_width() const;
  XYSeries result() const;

 private:
  struct Bucket {
    double x_min = 0.0, y_min = 0.0;              // smallest finite y and its x
    double x_max = 0.0, y_max = 0.0;              // largest finite y and its x
    std::size_t i_min = 0, i_max = 0, i_nan = 0;  // sample numbers, to keep the order
    bool finite = false;
    bool nan = false;
  };
  static Bucket merged(const Bucket& a, const Bucket& b);
  static void add(Bucket& bucket, double x, double y, std::size_t i);
  void halve();

  std::size_t max_buckets_;
  std::size_t width_ = 1;    // samples per bucket
  std::size_t in_last_ = 0;  // samples in the last bucket
  std::size_t samples_ = 0;
  std::vector<Bucket> buckets_;
};

// The same for a series held in memory. x may be null (x = sample index).
XYSeries downsample_min_max(const double* x, const double* y, std::size_t n,
                            int max_buckets = 2000);

}  // namespace redpost::report
