// Myers' O(ND) difference in linear space (the bisection of diff-match-patch), with a work
// budget (krl/diff_align.hpp).
#include "krl/diff_align.hpp"

#include <cstddef>

namespace redpost::krl {

namespace {

class Differ {
 public:
  Differ(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b) : a_(a), b_(b) {}

  std::vector<Step> run() {
    struct Task {
      bool emit_matches;
      size_t a0, a1, b0, b1;
    };
    std::vector<Task> stack{{false, 0, a_.size(), 0, b_.size()}};
    while (!stack.empty()) {
      Task t = stack.back();
      stack.pop_back();
      if (t.emit_matches) {
        for (size_t k = 0; k < t.a1 - t.a0; ++k)
          out_.push_back({Op::match, u32(t.a0 + k), u32(t.b0 + k)});
        continue;
      }
      // Common prefix, then common suffix (emitted after the middle).
      while (t.a0 < t.a1 && t.b0 < t.b1 && a_[t.a0] == b_[t.b0]) {
        out_.push_back({Op::match, u32(t.a0), u32(t.b0)});
        ++t.a0;
        ++t.b0;
      }
      size_t s = 0;
      while (t.a1 - s > t.a0 && t.b1 - s > t.b0 && a_[t.a1 - s - 1] == b_[t.b1 - s - 1])
        ++s;
      if (s > 0)
        stack.push_back({true, t.a1 - s, t.a1, t.b1 - s, t.b1});
      t.a1 -= s;
      t.b1 -= s;
      if (t.a0 == t.a1 || t.b0 == t.b1) {
        emit_mismatch(t.a0, t.a1, t.b0, t.b1);
        continue;
      }
      size_t x = 0, y = 0;
      if (!bisect(t.a0, t.a1, t.b0, t.b1, x, y)) {
        emit_mismatch(t.a0, t.a1, t.b0, t.b1);
        continue;
      }
      stack.push_back({false, t.a0 + x, t.a1, t.b0 + y, t.b1});
      stack.push_back({false, t.a0, t.a0 + x, t.b0, t.b0 + y});
    }
    return std::move(out_);
  }

 private:
  static uint32_t u32(size_t v) { return static_cast<uint32_t>(v); }

  void emit_mismatch(size_t a0, size_t a1, size_t b0, size_t b1) {
    for (size_t i = a0; i < a1; ++i)
      out_.push_back({Op::del, u32(i), 0});
    for (size_t j = b0; j < b1; ++j)
      out_.push_back({Op::ins, 0, u32(j)});
  }

  // The middle snake of a[a0, a1) against b[b0, b1): a split point (x, y) of an optimal path.
  // False when none is found within the work budget (the region is then left unaligned).
  bool bisect(size_t a0, size_t a1, size_t b0, size_t b1, size_t& split_x, size_t& split_y) {
    const long n = static_cast<long>(a1 - a0), m = static_cast<long>(b1 - b0);
    const long max_d = (n + m + 1) / 2;
    const long offset = max_d, length = 2 * max_d + 2;
    std::vector<long> v1(static_cast<size_t>(length), -1), v2(static_cast<size_t>(length), -1);
    v1[static_cast<size_t>(offset + 1)] = 0;
    v2[static_cast<size_t>(offset + 1)] = 0;
    const long delta = n - m;
    const bool front = (delta % 2) != 0;
    long k1start = 0, k1end = 0, k2start = 0, k2end = 0;
    auto A = [&](long i) { return a_[a0 + static_cast<size_t>(i)]; };
    auto B = [&](long j) { return b_[b0 + static_cast<size_t>(j)]; };
    for (long d = 0; d < max_d; ++d) {
      // Work budget: about (n + m) per d; give up on hopeless regions (docs/krl-diff.md).
      work_ += static_cast<double>(2 * d + 2);
      if (work_ > kMaxWork)
        return false;
      for (long k1 = -d + k1start; k1 <= d - k1end; k1 += 2) {
        const long k1o = offset + k1;
        long x1 =
            (k1 == -d || (k1 != d && v1[k1o - 1] < v1[k1o + 1])) ? v1[k1o + 1] : v1[k1o - 1] + 1;
        long y1 = x1 - k1;
        const long start1 = x1;
        while (x1 < n && y1 < m && A(x1) == B(y1)) {
          ++x1;
          ++y1;
        }
        work_ += static_cast<double>(x1 - start1);
        v1[k1o] = x1;
        if (x1 > n) {
          k1end += 2;
        } else if (y1 > m) {
          k1start += 2;
        } else if (front) {
          const long k2o = offset + delta - k1;
          if (k2o >= 0 && k2o < length && v2[k2o] != -1 && x1 >= n - v2[k2o]) {
            split_x = static_cast<size_t>(x1);
            split_y = static_cast<size_t>(y1);
            return true;
          }
        }
      }
      for (long k2 = -d + k2start; k2 <= d - k2end; k2 += 2) {
        const long k2o = offset + k2;
        long x2 =
            (k2 == -d || (k2 != d && v2[k2o - 1] < v2[k2o + 1])) ? v2[k2o + 1] : v2[k2o - 1] + 1;
        long y2 = x2 - k2;
        const long start2 = x2;
        while (x2 < n && y2 < m && A(n - x2 - 1) == B(m - y2 - 1)) {
          ++x2;
          ++y2;
        }
        work_ += static_cast<double>(x2 - start2);
        v2[k2o] = x2;
        if (x2 > n) {
          k2end += 2;
        } else if (y2 > m) {
          k2start += 2;
        } else if (!front) {
          const long k1o = offset + delta - k2;
          if (k1o >= 0 && k1o < length && v1[k1o] != -1) {
            const long x1 = v1[k1o];
            const long y1 = offset + x1 - k1o;
            if (x1 >= n - x2) {
              split_x = static_cast<size_t>(x1);
              split_y = static_cast<size_t>(y1);
              return true;
            }
          }
        }
      }
    }
    return false;
  }

  static constexpr double kMaxWork = 4e8;
  const std::vector<uint64_t>& a_;
  const std::vector<uint64_t>& b_;
  std::vector<Step> out_;
  double work_ = 0.0;
};

}  // namespace

std::vector<Step> align_keys(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b) {
  return Differ(a, b).run();
}

}  // namespace redpost::krl
