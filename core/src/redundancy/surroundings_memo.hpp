// The links around the arm (ArmIk::before_arm, after_arm) remembered per setting of the joints
// outside the arm, for the whole-path planner's lattice nodes.
//
// A keyframe's few hundred nodes share a handful of settings of the table and the track (the
// chain before A1) and of the spin (after A6): the beam's nodes one lattice step apart. Composing
// those links per node was 7 % of a conversion's time (docs/performance.md). The memo is a pure
// function's cache: an entry is found only when the ArmIk (its instance number) and every value it
// depends on are the same bit for bit, so the solutions are the same as without it, on any thread
// and in any order. One memo per thread (the planner's node loop runs on a pool), direct-mapped: a
// collision only costs a recompute.
// The cell must not change while its solver lives, as ArmIk itself assumes (its geometry is
// taken from the cell once).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>

#include "redpost/kinematics/arm_ik.hpp"

namespace redpost::detail {

class SurroundingsMemo {
 public:
  // The links before A1 at q_other for ik, composed or remembered.
  const ArmBefore& before(const ArmIk& ik, const JointVector& q_other) {
    Entry<ArmBefore>& e = find(before_, ik, q_other, 0, ik.arm_joints()[0]);
    if (!e.filled) {
      ik.before_arm(q_other, e.frames);
      e.filled = true;
    }
    return e.frames;
  }
  // The links after A6.
  const ArmAfter& after(const ArmIk& ik, const JointVector& q_other) {
    Entry<ArmAfter>& e =
        find(after_, ik, q_other, ik.arm_joints()[5] + 1, static_cast<int>(q_other.size()));
    if (!e.filled) {
      ik.after_arm(q_other, e.frames);
      e.filled = true;
    }
    return e.frames;
  }

 private:
  static constexpr std::size_t kSlots = 64;

  template <class Frames>
  struct Entry {
    std::uint64_t ik = 0;  // ArmIk::instance(), 0: empty
    int begin = 0, end = 0;
    std::array<std::uint64_t, kMaxJoints> key{};  // the values' bits
    bool filled = false;
    Frames frames;
  };

  // The entry for the values q[begin, end): the remembered one, or a cleared slot (filled false)
  // keyed by them.
  template <class Frames>
  static Entry<Frames>& find(std::array<Entry<Frames>, kSlots>& table, const ArmIk& ik,
                             const JointVector& q, int begin, int end) {
    // The values' bits: a few joints, so hashed and compared in a plain loop (a memcmp call
    // was 2.6 % of the planning thread).
    std::array<std::uint64_t, kMaxJoints> bits{};
    const int n = end - begin;
    std::uint64_t h = 1469598103934665603ULL;  // FNV-1a
    for (int k = 0; k < n; ++k) {
      std::memcpy(&bits[static_cast<std::size_t>(k)], &q[begin + k], sizeof(double));
      h = (h ^ bits[static_cast<std::size_t>(k)]) * 1099511628211ULL;
    }
    Entry<Frames>& e = table[(h ^ (h >> 29)) % kSlots];
    bool same = e.ik == ik.instance() && e.begin == begin && e.end == end;
    for (int k = 0; k < n && same; ++k)
      same = e.key[static_cast<std::size_t>(k)] == bits[static_cast<std::size_t>(k)];
    if (same)
      return e;
    e.ik = ik.instance();
    e.begin = begin;
    e.end = end;
    e.key = bits;
    e.filled = false;
    return e;
  }

  std::array<Entry<ArmBefore>, kSlots> before_{};
  std::array<Entry<ArmAfter>, kSlots> after_{};
};

}  // namespace redpost::detail
