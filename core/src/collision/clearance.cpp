// Conservative advancement along the written motions (clearance.hpp, docs/collision.md).
#include "redpost/collision/clearance.hpp"

#include <algorithm>
#include <cmath>

namespace redpost {

struct ClearanceMonitor::Node {
  double s = 0.0;
  JointVector q;
  KinematicsData data;
  ScenePoses poses;
  std::vector<double> lb;  // per pair: a lower bound of its distance at q
};

ClearanceMonitor::ClearanceMonitor(const CollisionScene& scene, const ClearanceSettings& settings)
    : scene_(&scene), settings_(settings) {
  nodes_.resize(static_cast<std::size_t>(settings.max_depth + 3));
  for (Node& n : nodes_) {
    scene.prepare(n.poses);
    n.lb.assign(scene.pairs().size(), 0.0);
    n.q.setZero(scene.cell().size());
  }
  blend_.assign(scene.pairs().size(), 0.0);
  last_motion_.assign(scene.pairs().size(), 0.0);
}

ClearanceMonitor::~ClearanceMonitor() = default;

ClearanceShortfall shortfall(const MotionClearance& c) {
  // A least that no distance computation gave (where.exact false) is a bound.
  if (c.unproven && !c.where.exact)
    return ClearanceShortfall::unproven;
  if (c.least_mm <= 0.0)
    return ClearanceShortfall::touching;
  return c.unproven ? ClearanceShortfall::unproven : ClearanceShortfall::too_close;
}

double posture_clearance(const CollisionScene& scene, const JointVector& q, double enough,
                         ScenePoses& poses, KinematicsData& data, int* pair) {
  const Cell& cell = scene.cell();
  JointVector qp = q;
  for (int i = 0; i < cell.size(); ++i) {
    if (cell.joint(i).type == JointType::virtual_spin)
      qp[i] = 0.0;
  }
  forward_kinematics(cell, qp, data, true);
  scene.place(data, poses);
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < scene.pairs().size(); ++p) {
    const double d = scene.distance(static_cast<int>(p), poses, enough);
    if (d < least) {
      least = d;
      if (pair)
        *pair = static_cast<int>(p);
    }
    if (least < enough)
      break;
  }
  return least;
}

const JointVector& ClearanceMonitor::q() const {
  return node(0).q;
}

ClearanceMonitor::Node& ClearanceMonitor::node(int i) {
  return nodes_[static_cast<std::size_t>(i)];
}
const ClearanceMonitor::Node& ClearanceMonitor::node(int i) const {
  return nodes_[static_cast<std::size_t>(i)];
}

void ClearanceMonitor::set_posture(Node& n, const JointVector& q) {
  const Cell& cell = scene_->cell();
  n.q = q;
  // The tool's spin is no motion of the robot: no body turns with it (the loader refuses
  // bodies on it; the tool's cylinders are round about it).
  for (int i = 0; i < cell.size(); ++i) {
    if (cell.joint(i).type == JointType::virtual_spin)
      n.q[i] = 0.0;
  }
  forward_kinematics(cell, n.q, n.data, true);
  scene_->place(n.data, n.poses);
}

namespace {

// An exact distance computed on the motion.
void sampled(MotionClearance& out, double d, int pair, const Proximity& where) {
  if (where.exact && d < out.nearest_mm) {
    out.nearest_mm = d;
    out.nearest_pair = pair;
    out.nearest_where = where;
  }
}

void note(MotionClearance& out, double d, int pair, double s, const Proximity& where) {
  if (std::isnan(d))
    d = 0.0;  // no distance (a body of absurd size): as bad as touching
  if (d < out.least_mm) {
    out.least_mm = d;
    out.pair = pair;
    out.s = s;
    out.where = where;
  }
}

}  // namespace

void ClearanceMonitor::compute(Node& n, bool fresh, MotionClearance& out, double s) {
  const double exact_below = settings_.margin_mm + settings_.exact_within_mm;
  for (std::size_t p = 0; p < scene_->pairs().size(); ++p) {
    Proximity where;
    double d = scene_->distance(static_cast<int>(p), n.poses, exact_below, &where);
    ++queries_;
    ++out.distance_queries;
    if (fresh && d > 0.0 && scene_->inside(static_cast<int>(p), n.poses)) {
      d = 0.0;  // wholly inside a closed mesh: as bad as touching it
      where.exact = true;
      where.distance_mm = 0.0;
    }
    n.lb[p] = d;
    note(out, d, static_cast<int>(p), s, where);
    sampled(out, d, static_cast<int>(p), where);
    if (!(d >= settings_.margin_mm))
      out.clear = false;
  }
}

MotionClearance ClearanceMonitor::start(const JointVector& q) {
  MotionClearance out;
  Node& a = node(0);
  set_posture(a, q);
  a.s = 0.0;
  std::fill(last_motion_.begin(), last_motion_.end(), 0.0);
  compute(a, true, out, 0.0);
  started_ = true;
  return out;
}

void ClearanceMonitor::bound(const Node& a, const Node& b, const Node* mid, double allowance,
                             std::vector<double>& pair_bound) {
  JointVector dq = (b.q - a.q).cwiseAbs();
  if (mid)
    dq += 2.0 * (mid->q - 0.5 * (a.q + b.q)).cwiseAbs();
  scene_->motion_bounds(a.data, a.poses, dq, body_bound_);
  const auto& pairs = scene_->pairs();
  pair_bound.resize(pairs.size());
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    // The allowances stray each body that moves; one on {B} stays.
    const double extra = (scene_->body(pairs[p].a).frame == kFrameBase ? 0.0 : allowance) +
                         (scene_->body(pairs[p].b).frame == kFrameBase ? 0.0 : allowance) +
                         blend_[p];
    pair_bound[p] =
        settings_.bound_scale * (scene_->pair_motion(static_cast<int>(p), body_bound_) + extra);
  }
}

// The piece of `path` between nodes a and b, for the pairs not yet proven on it (both nodes'
// bounds known for them): halved at its middle until each is proven or found too close.
void ClearanceMonitor::interval(const JointPath& path, int depth, const Node& a, const Node& b,
                                const std::vector<int>& pairs, MotionClearance& out) {
  if (depth >= settings_.max_depth || ++pieces_ > settings_.max_pieces) {
    for (int p : pairs) {
      const auto pu = static_cast<std::size_t>(p);
      note(out, std::min(a.lb[pu], b.lb[pu]), p, a.s, Proximity{});
    }
    out.clear = false;  // not proven within the halvings allowed
    out.unproven = true;
    return;
  }
  Node& m = node(2 + depth);
  m.s = 0.5 * (a.s + b.s);
  JointVector qm;
  if (!path.at(m.s, qm)) {
    out.clear = false;
    out.path_lost = true;  // no distance: the arm cannot follow the path there
    out.s = m.s;
    return;
  }
  set_posture(m, qm);
  std::vector<double> pb;
  bound(a, b, path.joint_linear() ? nullptr : &m, path.allowance_mm, pb);
  std::vector<int> open;
  const double exact_below = settings_.margin_mm + settings_.exact_within_mm;
  for (int p : pairs) {
    const auto pu = static_cast<std::size_t>(p);
    const double proven = std::max(a.lb[pu], b.lb[pu]) - pb[pu];
    if (proven >= settings_.margin_mm - settings_.resolution_mm) {
      note(out, proven, p, a.lb[pu] < b.lb[pu] ? a.s : b.s, Proximity{});
      continue;
    }
    // What does not shrink with the piece (the blend's and the path's allowances) already
    // leaves no room: halving cannot prove it.
    const double fixed = settings_.bound_scale * (blend_[pu] + 2.0 * path.allowance_mm);
    if (std::max(a.lb[pu], b.lb[pu]) - fixed < settings_.margin_mm - settings_.resolution_mm) {
      note(out, std::max(a.lb[pu], b.lb[pu]) - fixed, p, m.s, Proximity{});
      out.clear = false;
      out.unproven = true;  // a bound that cannot close, not a distance found
      continue;
    }
    Proximity where;
    m.lb[pu] = scene_->distance(p, m.poses, exact_below, &where);
    ++queries_;
    ++out.distance_queries;
    sampled(out, m.lb[pu], p, where);
    if (!(m.lb[pu] >= settings_.margin_mm)) {
      // An exact distance below the margin (or not a number): found.
      note(out, m.lb[pu], p, m.s, where);
      out.clear = false;
      continue;
    }
    open.push_back(p);
  }
  if (open.empty())
    return;
  interval(path, depth + 1, a, m, open, out);
  interval(path, depth + 1, m, b, open, out);
}

MotionClearance ClearanceMonitor::advance(const JointPath& path) {
  MotionClearance out;
  Node& a = node(0);
  Node& b = node(1);
  JointVector q1;
  if (!path.at(1.0, q1)) {
    out.clear = false;
    out.path_lost = true;
    return out;
  }
  set_posture(b, q1);
  b.s = 1.0;
  // The middle, for a Cartesian path's distance from its chord.
  Node& m = node(2);
  const bool curved = !path.joint_linear();
  if (curved) {
    JointVector qm;
    if (!path.at(0.5, qm)) {
      out.clear = false;
      out.path_lost = true;
      out.s = 0.5;
      return out;
    }
    m.q = qm;
    for (int i = 0; i < scene_->cell().size(); ++i) {
      if (scene_->cell().joint(i).type == JointType::virtual_spin)
        m.q[i] = 0.0;
    }
  }
  // The blend's allowance per body: its fraction of the whole motion's bound.
  std::fill(blend_.begin(), blend_.end(), 0.0);
  std::vector<double>& pb = pair_bound_;
  bound(a, b, curved ? &m : nullptr, path.allowance_mm, pb);
  if (path.blend_fraction > 0.0 || path.blend_fraction_before > 0.0) {
    for (std::size_t p = 0; p < blend_.size(); ++p) {
      const double whole = scene_->pair_motion(static_cast<int>(p), body_bound_);
      blend_[p] = path.blend_fraction * whole + path.blend_fraction_before * last_motion_[p];
      last_motion_[p] = whole;
    }
    bound(a, b, curved ? &m : nullptr, path.allowance_mm, pb);
  } else {
    for (std::size_t p = 0; p < last_motion_.size(); ++p)
      last_motion_[p] = scene_->pair_motion(static_cast<int>(p), body_bound_);
  }
  const double refresh_below = settings_.margin_mm + settings_.refresh_within_mm;
  const double exact_below = settings_.margin_mm + settings_.exact_within_mm;
  open_.clear();
  for (std::size_t p = 0; p < pb.size(); ++p) {
    double end = a.lb[p] - pb[p];
    Proximity where;
    if (end < refresh_below) {
      const double d = scene_->distance(static_cast<int>(p), b.poses, exact_below, &where);
      end = std::max(end, d);
      ++queries_;
      ++out.distance_queries;
      sampled(out, d, static_cast<int>(p), where);
    }
    b.lb[p] = end;
    const double proven = std::max(a.lb[p], end) - pb[p];
    if (proven >= settings_.margin_mm - settings_.resolution_mm) {
      note(out, proven, static_cast<int>(p), 1.0, where);
      continue;
    }
    if (end < settings_.margin_mm && where.exact) {
      note(out, end, static_cast<int>(p), 1.0, where);  // the end itself is too close
      out.clear = false;
      continue;
    }
    open_.push_back(static_cast<int>(p));
  }
  if (!open_.empty()) {
    pieces_ = 0;
    const std::vector<int> open = open_;
    interval(path, 0, a, b, open, out);
  }
  std::swap(nodes_[0], nodes_[1]);
  node(0).s = 0.0;
  return out;
}

MotionClearance ClearanceMonitor::probe(const JointPath& path) {
  const Node saved = node(0);
  const bool was_started = started_;
  const std::vector<double> saved_last = last_motion_;
  JointVector q0;
  MotionClearance out;
  if (!path.at(0.0, q0)) {
    out.clear = false;
    return out;
  }
  MotionClearance first = start(q0);
  MotionClearance rest = advance(path);
  if (first.least_mm < rest.least_mm) {
    rest.least_mm = first.least_mm;
    rest.pair = first.pair;
    rest.s = 0.0;
    rest.where = first.where;
  }
  if (first.nearest_mm < rest.nearest_mm) {
    rest.nearest_mm = first.nearest_mm;
    rest.nearest_pair = first.nearest_pair;
    rest.nearest_where = first.nearest_where;
  }
  rest.clear = rest.clear && first.clear;
  rest.distance_queries += first.distance_queries;
  node(0) = saved;
  started_ = was_started;
  last_motion_ = saved_last;
  return rest;
}

}  // namespace redpost
