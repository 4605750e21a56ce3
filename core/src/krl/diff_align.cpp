// Myers' O(ND) difference in linear space (the bisection of diff-match-patch), with patience
// anchors in large regions and a work budget (krl/diff_align.hpp).
#include "krl/diff_align.hpp"

#include <algorithm>
#include <cstddef>
#include <unordered_map>

namespace redpost::krl {

namespace {

class Differ {
 public:
  Differ(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b, AlignBudget& budget)
      : a_(a), b_(b), budget_(budget) {}

  std::vector<Step> run() {
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
      if ((t.a1 - t.a0) + (t.b1 - t.b0) > kAnchorRegion && anchor(t.a0, t.a1, t.b0, t.b1, stack))
        continue;
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
  struct Task {
    bool emit_matches;
    size_t a0, a1, b0, b1;
  };

  static uint32_t u32(size_t v) { return static_cast<uint32_t>(v); }

  // Patience anchors for a large region: keys that occur once in each side, the longest run of
  // them in the same order on both (a longest increasing subsequence), become matches, and the
  // gaps between them are aligned on their own. An inserted block of thousands of motions then
  // costs its length, not Myers' (n + m) D. False when there is no such key.
  bool anchor(size_t a0, size_t a1, size_t b0, size_t b1, std::vector<Task>& stack) {
    struct Count {
      uint32_t in_a = 0, in_b = 0, j = 0;
    };
    std::unordered_map<uint64_t, Count> counts;
    counts.reserve(a1 - a0);
    for (size_t i = a0; i < a1; ++i)
      ++counts[a_[i]].in_a;
    for (size_t j = b0; j < b1; ++j) {
      const auto it = counts.find(b_[j]);
      if (it != counts.end() && it->second.in_b++ == 0)
        it->second.j = u32(j);
    }
    std::vector<std::pair<uint32_t, uint32_t>> unique;  // (i, j), ascending in i
    for (size_t i = a0; i < a1; ++i) {
      const Count& c = counts.find(a_[i])->second;
      if (c.in_a == 1 && c.in_b == 1)
        unique.emplace_back(u32(i), c.j);
    }
    if (unique.empty())
      return false;
    // Longest increasing subsequence in j: tails[k], the index in `unique` of the smallest j
    // that ends an increasing run of length k + 1; prev links each to its predecessor.
    std::vector<size_t> tails, prev(unique.size());
    for (size_t u = 0; u < unique.size(); ++u) {
      const auto pos = std::lower_bound(tails.begin(), tails.end(), unique[u].second,
                                        [&](size_t t, uint32_t j) { return unique[t].second < j; });
      prev[u] = pos == tails.begin() ? unique.size() : *(pos - 1);
      if (pos == tails.end())
        tails.push_back(u);
      else
        *pos = u;
    }
    // Tasks in reverse order (a stack): the gap after each anchor, the anchor, ..., the first gap.
    size_t end_a = a1, end_b = b1;
    for (size_t u = tails.back(); u != unique.size(); u = prev[u]) {
      const size_t i = unique[u].first, j = unique[u].second;
      if (i + 1 < end_a || j + 1 < end_b)
        stack.push_back({false, i + 1, end_a, j + 1, end_b});
      stack.push_back({true, i, i + 1, j, j + 1});
      end_a = i;
      end_b = j;
    }
    if (a0 < end_a || b0 < end_b)
      stack.push_back({false, a0, end_a, b0, end_b});
    return true;
  }

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
      budget_.work_left -= static_cast<double>(2 * d + 2);
      if (budget_.work_left < 0.0) {
        budget_.exhausted = true;
        return false;
      }
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
        budget_.work_left -= static_cast<double>(x1 - start1);
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
        budget_.work_left -= static_cast<double>(x2 - start2);
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

  // Regions up to this many keys (both sides) go to Myers directly: it is cheap there, and gives
  // the shortest edit.
  static constexpr size_t kAnchorRegion = 4096;
  const std::vector<uint64_t>& a_;
  const std::vector<uint64_t>& b_;
  AlignBudget& budget_;
  std::vector<Step> out_;
};

}  // namespace

std::vector<Step> align_keys(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b,
                             AlignBudget& budget) {
  return Differ(a, b, budget).run();
}

}  // namespace redpost::krl
