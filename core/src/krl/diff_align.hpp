// Aligning two sequences of keys: Myers' O(ND) difference in linear space (the bisection of
// diff-match-patch), for the motion alignment of the KRL diff (diff.cpp). A region whose
// alignment takes too much work is left unaligned (docs/krl-diff.md).
#pragma once

#include <cstdint>
#include <vector>

namespace redpost::krl {

enum class Op : uint8_t { match, del, ins };
struct Step {
  Op op;
  uint32_t i;  // index in A (match, del)
  uint32_t j;  // index in B (match, ins)
};

// The work the alignments of one diff may take together: about (n + m) per edit, so that two
// unrelated programs still finish in seconds (docs/krl-diff.md).
struct AlignBudget {
  double work_left = 4e8;
  bool exhausted = false;  // some region was left unaligned for want of it
};

// The steps that turn `a` into `b`, in order: matches, deletions from A, insertions from B. A
// region whose alignment would take more than the budget is left unaligned: its motions are
// deletions and insertions (they are paired again in order by the caller).
std::vector<Step> align_keys(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b,
                             AlignBudget& budget);

}  // namespace redpost::krl
