// Two programs aligned and compared as they are read, a window of each (krl/diff_stream.hpp).
#include "krl/diff_stream.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <vector>

#include "krl/diff_align.hpp"
#include "krl/diff_compare.hpp"
#include "krl/diff_path.hpp"

namespace redpost::krl {

namespace {

// Below this a window cannot hold both halves the alignment needs.
constexpr std::size_t kMinWindow = 16;

class StreamDiff {
 public:
  StreamDiff(PoseSource& a, PoseSource& b, const KrlDiffOptions& o)
      : src_{&a, &b}, window_(std::max(o.window, kMinWindow)), cmp_(o, r_, paths()) {
    r_.window = window_;
  }

  KrlDiffResult run() {
    fill(0);
    fill(1);
    decide();
    while (!buf_[0].empty() || !buf_[1].empty()) {
      std::size_t committed = 0;
      if (by_cl_ && monotone_)
        committed = commit_by_cl();
      if (committed == 0)
        commit_by_key();
      fill(0);
      fill(1);
    }
    r_.budget_exhausted = budget_.exhausted;
    r_.equal = r_.difference_count == 0;
    return std::move(r_);
  }

 private:
  using Buffer = std::deque<DiffPose>;

  const PathWindow* const* paths() {
    path_ptrs_[0] = &path_[0];
    path_ptrs_[1] = &path_[1];
    return path_ptrs_;
  }

  // The motions of side s that may be committed now: half the buffer, so that the other
  // program's path and alignment are known half a window ahead; all of it at the end.
  std::size_t limit(int s) const {
    const std::size_t n = buf_[s].size();
    return eof_[s] ? n : n / 2;
  }

  void fill(int s) {
    Buffer& buf = buf_[s];
    while (!eof_[s] && buf.size() < window_) {
      DiffPose p;
      if (!src_[s]->next(p)) {
        eof_[s] = true;
        break;
      }
      (s == 0 ? r_.motions_a : r_.motions_b) += 1;
      has_cl_[s] = has_cl_[s] || p.cl_line > 0;
      // Runs of equal CL line may be walked only while the CL lines never go back.
      monotone_ = monotone_ && p.cl_line >= last_cl_[s];
      last_cl_[s] = p.cl_line;
      buf.push_back(p);
      if (decided_)
        to_path(s, buf.back());
    }
  }

  void to_path(int s, const DiffPose& p) {
    // A motion to an axis target (or a relative one) between two Cartesian motions breaks the
    // polyline.
    if (!p.on_cartesian_path()) {
      broken_[s] = true;
      return;
    }
    path_[s].push({p.xyz, p.abc, broken_[s], p.seq});
    broken_[s] = false;
  }

  // Once the first window of each is read: how to align, and the path grid's cell (the typical
  // segment's length, at least 1 mm).
  void decide() {
    by_cl_ = has_cl_[0] && has_cl_[1];
    r_.aligned_by_cl_line = by_cl_;
    double cell = 1.0;
    for (int s = 0; s < 2; ++s) {
      std::vector<double> lengths;
      const DiffPose* prev = nullptr;
      for (const DiffPose& p : buf_[s]) {
        if (!p.on_cartesian_path()) {
          prev = nullptr;
          continue;
        }
        if (prev)
          lengths.push_back(std::hypot(p.xyz[0] - prev->xyz[0], p.xyz[1] - prev->xyz[1],
                                       p.xyz[2] - prev->xyz[2]));
        prev = &p;
      }
      if (lengths.empty())
        continue;
      std::nth_element(lengths.begin(), lengths.begin() + static_cast<long>(lengths.size() / 2),
                       lengths.end());
      cell = std::max(cell, lengths[lengths.size() / 2]);
    }
    for (int s = 0; s < 2; ++s) {
      path_[s].set_cell(cell);
      for (const DiffPose& p : buf_[s])
        to_path(s, p);
    }
    decided_ = true;
  }

  // The first n motions of side s are compared: out of the buffer, and the path more than a
  // quarter window behind dropped.
  void advance(int s, std::size_t n) {
    Buffer& buf = buf_[s];
    buf.erase(buf.begin(), buf.begin() + static_cast<long>(n));
    const std::uint64_t cursor =
        buf.empty() ? (s == 0 ? r_.motions_a : r_.motions_b) : buf.front().seq;
    const std::uint64_t back = window_ / 4;
    if (cursor > back)
      path_[s].drop_before(cursor - back);
  }

  std::size_t run_end(const Buffer& buf, std::size_t i) const {
    std::size_t e = i;
    while (e < buf.size() && buf[e].cl_line == buf[i].cl_line)
      ++e;
    return e;
  }

  // The merge walk on CL lines: runs of equal CL line on both sides are aligned with each other;
  // a run whose CL line the other side skips is removed (inserted). Only runs complete and
  // within the limits; returns the motions committed.
  std::size_t commit_by_cl() {
    const Buffer &A = buf_[0], &B = buf_[1];
    const std::size_t na = A.size(), nb = B.size(), lim_a = limit(0), lim_b = limit(1);
    std::size_t ia = 0, ib = 0;
    // Each run's end is found once, not again while the other side walks past it.
    std::size_t ea = 0, eb = 0, ea_of = SIZE_MAX, eb_of = SIZE_MAX;
    while (ia < na || ib < nb) {
      if (ea_of != ia) {
        ea = ia < na ? run_end(A, ia) : ia;
        ea_of = ia;
      }
      if (eb_of != ib) {
        eb = ib < nb ? run_end(B, ib) : ib;
        eb_of = ib;
      }
      const bool ok_a = ia < na && (ea < na || eof_[0]) && ea <= lim_a;
      const bool ok_b = ib < nb && (eb < nb || eof_[1]) && eb <= lim_b;
      const int ca = ia < na ? A[ia].cl_line : 0, cb = ib < nb ? B[ib].cl_line : 0;
      if (ia < na && ib < nb && ca == cb) {
        if (!ok_a || !ok_b)
          break;
        align(ia, ea, ib, eb, false);
        ia = ea;
        ib = eb;
      } else if (ia < na && (ib < nb ? ca < cb : eof_[1])) {
        // No motion of B can have this CL line: the run is removed, as far as the limit even
        // if it goes on beyond the buffer (a CL line of thousands of motions).
        const std::size_t e = std::min(ea, lim_a);
        if (e == ia)
          break;
        for (; ia < e; ++ia)
          cmp_.only(A[ia], false);
      } else if (ib < nb && (ia < na ? cb < ca : eof_[0])) {
        const std::size_t e = std::min(eb, lim_b);
        if (e == ib)
          break;
        for (; ib < e; ++ib)
          cmp_.only(B[ib], true);
      } else {
        break;
      }
    }
    advance(0, ia);
    advance(1, ib);
    return ia + ib;
  }

  std::vector<std::uint64_t> keys(const Buffer& buf, std::size_t from, std::size_t to) const {
    std::vector<std::uint64_t> k;
    k.reserve(to - from);
    for (std::size_t i = from; i < to; ++i)
      k.push_back(by_cl_ ? motion_key_with_cl(buf[i]) : buf[i].key);
    return k;
  }

  // A[ia, ea) aligned with B[ib, eb) and compared, all of it.
  void align(std::size_t ia, std::size_t ea, std::size_t ib, std::size_t eb, bool by_cl) {
    const std::vector<Step> steps =
        align_keys(keys(buf_[0], ia, ea), keys(buf_[1], ib, eb), budget_);
    emit(steps, steps.size(), ia, ib, by_cl);
  }

  // The first `count` steps compared (offsets: where the aligned ranges start in the buffers).
  void emit(const std::vector<Step>& steps, std::size_t count, std::size_t ia, std::size_t ib,
            bool by_cl) {
    std::vector<const DiffPose*> dels, ins;
    for (std::size_t k = 0; k < count; ++k) {
      const Step& s = steps[k];
      if (s.op == Op::match) {
        if (!dels.empty() || !ins.empty()) {
          flush_hunk(dels, ins, by_cl, cmp_);
          dels.clear();
          ins.clear();
        }
        cmp_.pair(buf_[0][ia + s.i], buf_[1][ib + s.j]);
      } else if (s.op == Op::del) {
        dels.push_back(&buf_[0][ia + s.i]);
      } else {
        ins.push_back(&buf_[1][ib + s.j]);
      }
    }
    if (!dels.empty() || !ins.empty())
      flush_hunk(dels, ins, by_cl, cmp_);
  }

  // Myers on the keys of both windows. The steps up to the last match in the windows' first
  // halves are committed (the rest is aligned again with more read); without one, up to the
  // first match; without any match, the first halves are paired in order and the region is
  // reported (its partners lie beyond the window, or the work budget ran out).
  void commit_by_key() {
    const std::size_t na = buf_[0].size(), nb = buf_[1].size();
    const std::vector<Step> steps = align_keys(keys(buf_[0], 0, na), keys(buf_[1], 0, nb), budget_);
    if (eof_[0] && eof_[1]) {
      emit(steps, steps.size(), 0, 0, by_cl_);
      advance(0, na);
      advance(1, nb);
      return;
    }
    const std::size_t lim_a = limit(0), lim_b = limit(1);
    std::size_t last = steps.size(), first = steps.size();
    for (std::size_t k = 0; k < steps.size(); ++k) {
      if (steps[k].op != Op::match)
        continue;
      if (first == steps.size())
        first = k;
      if (steps[k].i < lim_a && steps[k].j < lim_b)
        last = k;
    }
    const std::size_t upto = last != steps.size() ? last : first;
    if (upto != steps.size()) {
      emit(steps, upto + 1, 0, 0, by_cl_);
      advance(0, steps[upto].i + 1);
      advance(1, steps[upto].j + 1);
      return;
    }
    if (na > 0 && nb > 0 && r_.unaligned_regions++ == 0) {
      r_.unaligned_file_a = *buf_[0].front().file;
      r_.unaligned_line_a = buf_[0].front().line;
      r_.unaligned_file_b = *buf_[1].front().file;
      r_.unaligned_line_b = buf_[1].front().line;
    }
    std::vector<const DiffPose*> dels, ins;
    for (std::size_t i = 0; i < lim_a; ++i)
      dels.push_back(&buf_[0][i]);
    for (std::size_t j = 0; j < lim_b; ++j)
      ins.push_back(&buf_[1][j]);
    flush_hunk(dels, ins, by_cl_, cmp_);
    advance(0, lim_a);
    advance(1, lim_b);
  }

  KrlDiffResult r_;
  PoseSource* src_[2];
  std::size_t window_;
  Buffer buf_[2];
  bool eof_[2] = {false, false};
  bool has_cl_[2] = {false, false};
  int last_cl_[2] = {0, 0};
  bool monotone_ = true;
  bool decided_ = false, by_cl_ = false;
  bool broken_[2] = {true, true};
  PathWindow path_[2];
  const PathWindow* path_ptrs_[2] = {nullptr, nullptr};
  AlignBudget budget_;
  Comparer cmp_;
};

}  // namespace

KrlDiffResult diff_pose_streams(PoseSource& a, PoseSource& b, const KrlDiffOptions& options) {
  return StreamDiff(a, b, options).run();
}

}  // namespace redpost::krl
