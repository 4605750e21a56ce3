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

// The steps that turn `a` into `b`, in order: matches, deletions from A, insertions from B.
std::vector<Step> align_keys(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b);

}  // namespace redpost::krl
