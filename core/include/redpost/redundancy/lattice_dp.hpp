// Dynamic programming over a ladder graph whose rungs are points of a lattice of the free joints
// (the Descartes "ladder graph", planned by layers as in Gao et al. 2025's dynamic posture
// programming; docs/redundancy.md, "Whole-path planning").
//
// Layer k is a keyframe of the path. A node is a lattice key (an integer step count per free
// joint, and the arm's posture) with the joint vector the caller's evaluation gives it and a
// node cost; an edge joins nodes of consecutive layers whose keys differ by at most `reach` steps
// per free joint and share the posture. The layers are built forward: the nodes of layer k+1
// are the lattice neighbours of layer k's survivors, each with its cheapest parent (the cost to
// come), and only the `beam` cheapest survive into the next layer. With an unbounded beam this
// is the exact minimum over every sequence of keys that keeps to the reach (tested against
// brute force); the beam keeps the work per layer bounded.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "redpost/kinematics/types.hpp"

namespace redpost {

inline constexpr int kMaxFreeJoints = 3;

struct LatticeKey {
  std::array<int, kMaxFreeJoints> step{};  // per free joint, in lattice steps
  int posture = 0;

  bool operator==(const LatticeKey& o) const { return step == o.step && posture == o.posture; }
};

struct LatticeNode {
  LatticeKey key;
  JointVector q;
  double node_cost = 0.0;
  double cost = 0.0;  // cheapest cost to come, node costs of this node included
  int parent = -1;    // index in the previous layer
};

struct LatticeDpSettings {
  int free_joints = 0;                             // how many entries of LatticeKey::step are used
  std::array<int, kMaxFreeJoints> reach{1, 1, 1};  // largest step change between layers
  int beam = 48;                                   // nodes kept per layer (<= 0: all)
};

struct LatticeDpResult {
  bool feasible = false;
  int dead_layer = -1;            // first layer without any reachable node
  double cost = 0.0;              // of the path found
  std::vector<LatticeNode> path;  // one node per layer
  long evaluations = 0;           // nodes evaluated (for the benchmark)
};

namespace detail {

struct LatticeKeyHash {
  std::size_t operator()(const LatticeKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.posture) * 0x9E3779B97F4A7C15ull;
    for (int s : k.step)
      h = (h ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(s))) * 0x100000001B3ull;
    return static_cast<std::size_t>(h);
  }
};

inline bool within_reach(const LatticeKey& a, const LatticeKey& b, const LatticeDpSettings& s) {
  if (a.posture != b.posture)
    return false;
  for (int j = 0; j < s.free_joints; ++j) {
    if (std::abs(a.step[static_cast<std::size_t>(j)] - b.step[static_cast<std::size_t>(j)]) >
        s.reach[static_cast<std::size_t>(j)])
      return false;
  }
  return true;
}

inline void keep_beam(std::vector<LatticeNode>& layer, int beam) {
  if (beam <= 0 || static_cast<int>(layer.size()) <= beam)
    return;
  std::nth_element(layer.begin(), layer.begin() + beam, layer.end(),
                   [](const LatticeNode& a, const LatticeNode& b) { return a.cost < b.cost; });
  layer.resize(static_cast<std::size_t>(beam));
}

}  // namespace detail

// evaluate(layer, key, q, node_cost) -> bool: the joint vector of `key` at `layer` and its cost;
// false where the key is infeasible there (no inverse kinematics, a limit).
// edge(layer, from, to) -> double: the cost of going from `from` (layer - 1) to `to` (layer);
// +inf where forbidden.
template <class Evaluate, class Edge>
LatticeDpResult lattice_dp(int layers, const std::vector<LatticeKey>& first_keys,
                           const LatticeDpSettings& settings, Evaluate&& evaluate, Edge&& edge) {
  LatticeDpResult result;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::vector<LatticeNode>> kept(static_cast<std::size_t>(std::max(layers, 0)));
  for (int layer = 0; layer < layers; ++layer) {
    std::vector<LatticeNode>& here = kept[static_cast<std::size_t>(layer)];
    if (layer == 0) {
      for (const LatticeKey& key : first_keys) {
        LatticeNode n;
        n.key = key;
        ++result.evaluations;
        if (evaluate(0, key, n.q, n.node_cost) && std::isfinite(n.node_cost)) {
          n.cost = n.node_cost;
          here.push_back(n);
        }
      }
    } else {
      const std::vector<LatticeNode>& before = kept[static_cast<std::size_t>(layer - 1)];
      // The candidate keys: every neighbour of a survivor, once.
      std::unordered_map<LatticeKey, int, detail::LatticeKeyHash> seen;
      std::vector<LatticeKey> candidates;
      for (const LatticeNode& p : before) {
        std::array<int, kMaxFreeJoints> d{};
        const auto& r = settings.reach;
        for (d[0] = -r[0]; d[0] <= r[0]; ++d[0]) {
          for (d[1] = -r[1]; d[1] <= r[1]; ++d[1]) {
            for (d[2] = -r[2]; d[2] <= r[2]; ++d[2]) {
              bool unused_moves = false;
              for (int j = settings.free_joints; j < kMaxFreeJoints; ++j)
                unused_moves = unused_moves || d[static_cast<std::size_t>(j)] != 0;
              if (unused_moves)
                continue;
              LatticeKey k = p.key;
              for (int j = 0; j < settings.free_joints; ++j)
                k.step[static_cast<std::size_t>(j)] += d[static_cast<std::size_t>(j)];
              if (seen.emplace(k, static_cast<int>(candidates.size())).second)
                candidates.push_back(k);
            }
          }
        }
      }
      here.reserve(candidates.size());
      for (const LatticeKey& key : candidates) {
        LatticeNode n;
        n.key = key;
        ++result.evaluations;
        if (!evaluate(layer, key, n.q, n.node_cost) || !std::isfinite(n.node_cost))
          continue;
        n.cost = inf;
        for (std::size_t i = 0; i < before.size(); ++i) {
          if (!detail::within_reach(before[i].key, key, settings))
            continue;
          const double c = before[i].cost + edge(layer, before[i], n);
          if (c < n.cost) {
            n.cost = c;
            n.parent = static_cast<int>(i);
          }
        }
        if (n.parent >= 0 && std::isfinite(n.cost)) {
          n.cost += n.node_cost;
          here.push_back(n);
        }
      }
    }
    if (here.empty()) {
      result.dead_layer = layer;
      return result;
    }
    if (layer + 1 < layers)
      detail::keep_beam(here, settings.beam);
  }
  if (layers <= 0)
    return result;
  const std::vector<LatticeNode>& last = kept.back();
  const auto best =
      std::min_element(last.begin(), last.end(),
                       [](const LatticeNode& a, const LatticeNode& b) { return a.cost < b.cost; });
  result.feasible = true;
  result.cost = best->cost;
  result.path.resize(static_cast<std::size_t>(layers));
  int index = static_cast<int>(best - last.begin());
  for (int layer = layers - 1; layer >= 0; --layer) {
    const LatticeNode& n = kept[static_cast<std::size_t>(layer)][static_cast<std::size_t>(index)];
    result.path[static_cast<std::size_t>(layer)] = n;
    index = n.parent;
  }
  return result;
}

}  // namespace redpost
