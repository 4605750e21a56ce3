// Dynamic programming over a ladder graph whose rungs are points of a lattice of the free joints
// (the Descartes "ladder graph", planned by layers as in Gao et al. 2025's dynamic posture
// programming; docs/redundancy.md, "Whole-path planning").
//
// Layer k is a keyframe of the path. A node is a lattice key (an integer step count per free
// joint, and the arm's posture) with the joint vector the caller's evaluation gives it and a
// node cost; an edge joins nodes of consecutive layers whose keys differ by at most `reach` steps
// per free joint, in at most `max_moving` free joints, and share the posture. The layers are built
// forward: the nodes of layer k+1 are the lattice neighbours of layer k's survivors, each with its
// cheapest parent (the cost to come), and only the `beam` cheapest survive into the next layer.
// With an unbounded beam this is the exact minimum over every sequence of keys that keeps to the
// reach (tested against brute force); the beam keeps the work per layer bounded. An edge cost that
// reads the node's heading (the direction its free joints last stepped, LatticeNode::heading)
// depends on the way in, not on the node alone: the search is then a beam search over ways with
// their last direction (tested against an enumeration of every way).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "redpost/kinematics/types.hpp"
#include "redpost/redundancy/worker_pool.hpp"

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
  // Per free joint, the sign of its last step along the cheapest way to this node (0: it has
  // not moved yet): an edge cost may charge a reversal (docs/redundancy.md, "Costs"). The way
  // in is chosen by cost to come, so with such a cost the search is a beam search over paths
  // with their last direction, no longer the exact minimum.
  std::array<std::int8_t, kMaxFreeJoints> heading{};
};

struct LatticeDpSettings {
  int free_joints = 0;                             // how many entries of LatticeKey::step are used
  std::array<int, kMaxFreeJoints> reach{1, 1, 1};  // largest step change between layers
  int beam = 48;                                   // nodes kept per layer (<= 0: all)
  // Free joints that may change together between layers (the rest hold): fewer neighbours per
  // node. The planner lets two of three move at once; a move of all three is two keyframes'.
  int max_moving = kMaxFreeJoints;
  // Threads that evaluate a layer's nodes together (nullptr: the calling thread alone). The
  // `evaluate` callback is then called from several threads at once and must only read shared
  // state; the result is the same either way (each node written by one call).
  WorkerPool* pool = nullptr;
  // The first layer's headings (LatticeNode::heading): how the free joints last moved before it.
  std::array<std::int8_t, kMaxFreeJoints> first_heading{};
};

struct LatticeDpResult {
  bool feasible = false;
  int dead_layer = -1;            // first layer without any reachable node
  double cost = 0.0;              // of the path found
  std::vector<LatticeNode> path;  // one node per layer
  long evaluations = 0;           // nodes evaluated (for the benchmark)
  long refinements = 0;           // nodes refined (the lazy term asked)
};

namespace detail {

// f(0) ... f(n - 1): on the pool's threads when there is one.
template <class F>
void for_each_node(WorkerPool* pool, std::size_t n, const F& f) {
  if (pool) {
    pool->for_each(n, f);
    return;
  }
  for (std::size_t i = 0; i < n; ++i)
    f(i);
}

// The candidate keys of a layer, numbered in the order they are first met: an open-addressing
// table (linear probing, power-of-two size) that keeps its memory from layer to layer, because
// a node-based map's allocations were a tenth of the planner's time.
class KeyTable {
 public:
  // Clears the table for up to n keys.
  void reset(std::size_t n) {
    std::size_t size = 16;
    while (size < 2 * n)
      size *= 2;
    if (slots_.size() != size)
      slots_.assign(size, Slot{});
    else
      std::fill(slots_.begin(), slots_.end(), Slot{});
  }
  // The number of `key`: `next` (and stored so) when it is new.
  int find_or_add(const LatticeKey& key, int next) {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = hash(key) & mask;; i = (i + 1) & mask) {
      Slot& slot = slots_[i];
      if (slot.index < 0) {
        slot.key = key;
        slot.index = next;
        return next;
      }
      if (slot.key == key)
        return slot.index;
    }
  }

 private:
  struct Slot {
    LatticeKey key;
    int index = -1;
  };
  static std::size_t hash(const LatticeKey& k) {
    std::uint64_t h = static_cast<std::uint64_t>(k.posture) * 0x9E3779B97F4A7C15ull;
    for (int s : k.step)
      h = (h ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(s))) * 0x100000001B3ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
  std::vector<Slot> slots_;
};

inline void keep_beam(std::vector<LatticeNode>& layer, int beam) {
  if (beam <= 0 || static_cast<int>(layer.size()) <= beam)
    return;
  std::nth_element(layer.begin(), layer.begin() + beam, layer.end(),
                   [](const LatticeNode& a, const LatticeNode& b) { return a.cost < b.cost; });
  layer.resize(static_cast<std::size_t>(beam));
}

inline std::size_t neighbour_count(const LatticeDpSettings& s) {
  std::size_t n = 1;
  for (int j = 0; j < s.free_joints; ++j)
    n *= static_cast<std::size_t>(2 * s.reach[static_cast<std::size_t>(j)] + 1);
  return n;
}

// Calls f(key) for every key within reach of `centre` (centre included).
template <class F>
void for_each_neighbour(const LatticeKey& centre, const LatticeDpSettings& s, F&& f) {
  std::array<int, kMaxFreeJoints> lo{}, hi{};
  for (int j = 0; j < s.free_joints; ++j) {
    lo[static_cast<std::size_t>(j)] = -s.reach[static_cast<std::size_t>(j)];
    hi[static_cast<std::size_t>(j)] = s.reach[static_cast<std::size_t>(j)];
  }
  std::array<int, kMaxFreeJoints> d{};
  for (d[0] = lo[0]; d[0] <= hi[0]; ++d[0]) {
    for (d[1] = lo[1]; d[1] <= hi[1]; ++d[1]) {
      for (d[2] = lo[2]; d[2] <= hi[2]; ++d[2]) {
        if ((d[0] != 0) + (d[1] != 0) + (d[2] != 0) > s.max_moving)
          continue;
        LatticeKey k = centre;
        for (std::size_t j = 0; j < kMaxFreeJoints; ++j)
          k.step[j] += d[j];
        f(k);
      }
    }
  }
}

// The `beam` cheapest nodes of a layer whose costs so far are lower bounds, adding refine's
// non-negative extra cost (a costly term, such as the conditioning) lazily: nodes are refined
// in the order of their bounds, and the search stops once `beam` refined nodes cost no more than
// the next bound. The result is the beam an eager refinement of every node would keep (ties
// aside), with far fewer refinements where the extra cost is mostly zero.
template <class Refine>
void keep_beam_lazy(int layer, std::vector<LatticeNode>& nodes, int beam, Refine& refine,
                    long& refinements, WorkerPool* pool = nullptr) {
  std::vector<int> order(nodes.size());
  // The bounds packed for the sort (a node is 192 bytes: reading its cost through the index was
  // the DP's largest own cost); the same comparisons, so the same order.
  std::vector<double> bound(nodes.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = static_cast<int>(i);
    bound[i] = nodes[i].cost;
  }
  const auto cost_of = [&](int i) { return bound[static_cast<std::size_t>(i)]; };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return cost_of(a) < cost_of(b); });
  // The first `beam` nodes in that order are refined whatever their extra costs (the search
  // below stops only once `beam` nodes are kept): with a pool, refined together beforehand.
  const std::size_t ahead =
      pool ? std::min(order.size(), static_cast<std::size_t>(std::max(beam, 0))) : 0;
  std::vector<double> extra_ahead(ahead);
  if (ahead > 0) {
    for_each_node(pool, ahead, [&](std::size_t r) {
      extra_ahead[r] = refine(layer, nodes[static_cast<std::size_t>(order[r])]);
    });
  }
  std::vector<LatticeNode> kept;
  std::vector<double> worst;  // max-heap of the kept costs, at most `beam` of them
  for (std::size_t r = 0; r < order.size(); ++r) {
    LatticeNode& n = nodes[static_cast<std::size_t>(order[r])];
    if (beam > 0 && static_cast<int>(worst.size()) >= beam && worst.front() <= n.cost)
      break;
    ++refinements;
    const double extra = r < ahead ? extra_ahead[r] : refine(layer, n);
    if (!(extra >= 0.0) || !std::isfinite(extra))
      continue;
    n.node_cost += extra;
    n.cost += extra;
    kept.push_back(std::move(n));
    worst.push_back(kept.back().cost);
    std::push_heap(worst.begin(), worst.end());
    if (beam > 0 && static_cast<int>(worst.size()) > beam) {
      std::pop_heap(worst.begin(), worst.end());
      worst.pop_back();
    }
  }
  keep_beam(kept, beam);
  nodes.swap(kept);
}

}  // namespace detail

// evaluate(layer, key, q, node_cost) -> bool: the joint vector of `key` at `layer` and its cost;
// false where the key is infeasible there (no inverse kinematics, a limit).
// edge(layer, from, to) -> double: the cost of going from `from` (layer - 1) to `to` (layer);
// +inf where forbidden.
// refine(layer, node) -> double: a further non-negative node cost, asked only of the nodes that
// may enter the beam (detail::keep_beam_lazy); +inf or NaN drops the node.
template <class Evaluate, class Edge, class Refine>
LatticeDpResult lattice_dp(int layers, const std::vector<LatticeKey>& first_keys,
                           const LatticeDpSettings& settings, Evaluate&& evaluate, Edge&& edge,
                           Refine&& refine) {
  LatticeDpResult result;
  std::vector<std::vector<LatticeNode>> kept(static_cast<std::size_t>(std::max(layers, 0)));
  detail::KeyTable seen;
  std::vector<LatticeKey> candidates;
  std::vector<std::pair<int, int>> edges;        // (index in the layer before, candidate)
  std::vector<int> incoming_at, incoming, fill;  // the edges by candidate
  std::vector<char> valid;
  // A layer's candidate nodes, kept from layer to layer: value-initialising a few hundred
  // 192-byte nodes per layer was a tenth of the DP's own time. Each candidate sets every field
  // it is judged by.
  std::vector<LatticeNode> nodes;
  for (int layer = 0; layer < layers; ++layer) {
    std::vector<LatticeNode>& here = kept[static_cast<std::size_t>(layer)];
    if (layer == 0) {
      std::vector<LatticeNode> first(first_keys.size());
      valid.assign(first_keys.size(), 0);
      const auto evaluate_first = [&](std::size_t c) {
        LatticeNode& n = first[c];
        n.key = first_keys[c];
        n.heading = settings.first_heading;
        valid[c] = evaluate(0, n.key, n.q, n.node_cost) && std::isfinite(n.node_cost);
      };
      result.evaluations += static_cast<long>(first_keys.size());
      detail::for_each_node(settings.pool, first_keys.size(), evaluate_first);
      for (std::size_t c = 0; c < first.size(); ++c) {
        if (valid[c]) {
          first[c].cost = first[c].node_cost;
          here.push_back(std::move(first[c]));
        }
      }
    } else {
      const std::vector<LatticeNode>& before = kept[static_cast<std::size_t>(layer - 1)];
      // The candidate keys: every neighbour of a survivor, once; and every (survivor,
      // candidate) edge, in the survivors' order so that ties resolve as a plain scan would.
      seen.reset(before.size() * detail::neighbour_count(settings));
      candidates.clear();
      edges.clear();
      for (std::size_t i = 0; i < before.size(); ++i) {
        detail::for_each_neighbour(before[i].key, settings, [&](const LatticeKey& k) {
          const int c = seen.find_or_add(k, static_cast<int>(candidates.size()));
          if (c == static_cast<int>(candidates.size()))
            candidates.push_back(k);
          edges.emplace_back(static_cast<int>(i), c);
        });
      }
      // Each candidate's edges in the survivors' order (a stable bucketing of `edges`), so that
      // a candidate's cheapest parent is found as the plain scan over every edge finds it.
      incoming_at.assign(candidates.size() + 1, 0);
      for (const auto& [i, c] : edges)
        ++incoming_at[static_cast<std::size_t>(c) + 1];
      for (std::size_t c = 0; c < candidates.size(); ++c)
        incoming_at[c + 1] += incoming_at[c];
      incoming.resize(edges.size());
      fill.assign(incoming_at.begin(), incoming_at.end() - 1);
      for (const auto& [i, c] : edges)
        incoming[static_cast<std::size_t>(fill[static_cast<std::size_t>(c)]++)] = i;
      nodes.resize(candidates.size());
      valid.assign(candidates.size(), 0);
      // A candidate's node and its cheapest way in: independent of every other candidate's.
      const auto evaluate_node = [&](std::size_t c) {
        LatticeNode& n = nodes[c];
        n.key = candidates[c];
        n.cost = std::numeric_limits<double>::infinity();
        n.parent = -1;
        valid[c] = evaluate(layer, n.key, n.q, n.node_cost) && std::isfinite(n.node_cost);
        if (!valid[c])
          return;
        for (int e = incoming_at[c]; e < incoming_at[c + 1]; ++e) {
          const int i = incoming[static_cast<std::size_t>(e)];
          const LatticeNode& p = before[static_cast<std::size_t>(i)];
          const double cost = p.cost + edge(layer, p, n);
          if (cost < n.cost) {
            n.cost = cost;
            n.parent = i;
          }
        }
        if (n.parent >= 0) {
          const LatticeNode& p = before[static_cast<std::size_t>(n.parent)];
          for (std::size_t j = 0; j < kMaxFreeJoints; ++j) {
            const int d = n.key.step[j] - p.key.step[j];
            n.heading[j] = d > 0 ? 1 : d < 0 ? -1 : p.heading[j];
          }
        }
      };
      result.evaluations += static_cast<long>(candidates.size());
      detail::for_each_node(settings.pool, candidates.size(), evaluate_node);
      here.reserve(candidates.size());
      for (std::size_t c = 0; c < candidates.size(); ++c) {
        LatticeNode& n = nodes[c];
        if (valid[c] && n.parent >= 0 && std::isfinite(n.cost)) {
          n.cost += n.node_cost;
          here.push_back(std::move(n));
        }
      }
    }
    // The last layer keeps its cheapest node only.
    detail::keep_beam_lazy(layer, here, layer + 1 < layers ? settings.beam : 1, refine,
                           result.refinements, settings.pool);
    if (here.empty()) {
      result.dead_layer = layer;
      return result;
    }
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
  int at = static_cast<int>(best - last.begin());
  for (int layer = layers - 1; layer >= 0; --layer) {
    const LatticeNode& n = kept[static_cast<std::size_t>(layer)][static_cast<std::size_t>(at)];
    result.path[static_cast<std::size_t>(layer)] = n;
    at = n.parent;
  }
  return result;
}

// Without a lazy term.
template <class Evaluate, class Edge>
LatticeDpResult lattice_dp(int layers, const std::vector<LatticeKey>& first_keys,
                           const LatticeDpSettings& settings, Evaluate&& evaluate, Edge&& edge) {
  return lattice_dp(layers, first_keys, settings, std::forward<Evaluate>(evaluate),
                    std::forward<Edge>(edge), [](int, const LatticeNode&) { return 0.0; });
}

}  // namespace redpost
