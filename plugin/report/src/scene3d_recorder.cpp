// Scene3dRecorder (scene3d.hpp): the bounded, decimated copy of a program's motions that the 3D
// view draws.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "redpost/report/scene3d.hpp"

namespace redpost::report {

namespace {

constexpr float kNoValue = std::numeric_limits<float>::quiet_NaN();

double distance(const float a[3], const float b[3]) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

}  // namespace

Transform34 identity34() {
  return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
}

Scene3dRecorder::Scene3dRecorder(SceneCell cell, std::vector<SceneQuantity> quantities,
                                 Scene3dLimits limits)
    : cell_(std::move(cell)), quantities_(std::move(quantities)), limits_(limits) {
  if (cell_.links.empty() || cell_.links.size() > static_cast<std::size_t>(kSceneMaxJoints))
    throw std::invalid_argument("Scene3dRecorder: the cell needs 1 to 16 links");
  if (quantities_.size() > static_cast<std::size_t>(kSceneMaxQuantities))
    throw std::invalid_argument("Scene3dRecorder: at most 6 quantities");
  if (limits_.max_frames < 2 || limits_.max_path_points < 2)
    throw std::invalid_argument("Scene3dRecorder: the limits must allow two frames and points");
  frames_.reserve(static_cast<std::size_t>(limits_.max_frames) + 1);
  path_.reserve(limits_.max_path_points + 1);
}

Scene3dRecorder::Frame Scene3dRecorder::frame_of(const SceneMotion& m) const {
  Frame f;
  const int n = static_cast<int>(cell_.links.size());
  for (int i = 0; i < n; ++i)
    f.data[static_cast<std::size_t>(i)] = static_cast<float>(m.q[i]);
  const auto at = [&](int k) -> float& { return f.data[static_cast<std::size_t>(n + k)]; };
  at(0) = static_cast<float>(m.tool_length_mm);
  at(1) = static_cast<float>(m.tcp_shift_mm);
  for (int k = 0; k < 3; ++k)
    at(2 + k) = static_cast<float>(m.tcp_part_mm[k]);
  f.motion = static_cast<std::uint32_t>(m.index);
  f.line = static_cast<std::uint32_t>(std::max(0, m.cl_line));
  return f;
}

void Scene3dRecorder::add(const SceneMotion& m) {
  if (m.joint_count != static_cast<int>(cell_.links.size()) || !m.q) {
    throw std::invalid_argument("Scene3dRecorder: a motion with " + std::to_string(m.joint_count) +
                                " joints for a cell of " + std::to_string(cell_.links.size()));
  }
  ++motions_;
  last_ = frame_of(m);
  if ((motions_ - 1) % stride_ == 0) {
    frames_.push_back(last_);
    if (frames_.size() > static_cast<std::size_t>(limits_.max_frames)) {
      // Keep every second frame: those at multiples of the doubled stride.
      stride_ *= 2;
      std::size_t kept = 0;
      for (std::size_t i = 0; i < frames_.size(); i += 2)
        frames_[kept++] = frames_[i];
      frames_.resize(kept);
    }
  }
  add_path_point(m);
}

void Scene3dRecorder::merge_values(PathPoint& into, const PathPoint& from) const {
  for (std::size_t q = 0; q < quantities_.size(); ++q) {
    const float a = into.values[q], b = from.values[q];
    if (std::isnan(a)) {
      into.values[q] = b;
    } else if (!std::isnan(b) && !quantities_[q].categorical) {
      into.values[q] = quantities_[q].higher_is_better ? std::min(a, b) : std::max(a, b);
    }
  }
}

void Scene3dRecorder::add_path_point(const SceneMotion& m) {
  PathPoint p;
  for (int k = 0; k < 3; ++k)
    p.p[k] = static_cast<float>(m.tcp_part_mm[k]);
  p.motion = static_cast<std::uint32_t>(m.index);
  p.values.fill(kNoValue);
  for (std::size_t q = 0; q < quantities_.size() && m.values; ++q)
    p.values[q] = static_cast<float>(m.values[q]);
  if (!path_.empty() && distance(path_.back().p, p.p) < tol_mm_) {
    merge_values(path_.back(), p);
    return;
  }
  path_.push_back(p);
  while (path_.size() > limits_.max_path_points) {
    tol_mm_ *= 2.0;
    rethin();
  }
}

void Scene3dRecorder::rethin() {
  std::size_t kept = 1;
  for (std::size_t i = 1; i < path_.size(); ++i) {
    if (distance(path_[kept - 1].p, path_[i].p) < tol_mm_) {
      merge_values(path_[kept - 1], path_[i]);
    } else {
      path_[kept++] = path_[i];
    }
  }
  path_.resize(kept);
}

Scene3d Scene3dRecorder::scene() const {
  Scene3d s;
  s.cell = cell_;
  s.motions = motions_;
  s.frame_stride = stride_;
  s.path_tolerance_mm = tol_mm_;
  s.limits = limits_;
  const std::size_t width = cell_.links.size() + 5;
  auto push_frame = [&](const Frame& f) {
    s.frame_data.insert(s.frame_data.end(), f.data.begin(),
                        f.data.begin() + static_cast<std::ptrdiff_t>(width));
    s.frame_motion.push_back(f.motion);
    s.frame_line.push_back(f.line);
  };
  for (const Frame& f : frames_)
    push_frame(f);
  // The last motion, unless the stride kept it already.
  if (motions_ > 0 && (motions_ - 1) % stride_ != 0)
    push_frame(last_);
  for (const PathPoint& p : path_) {
    s.path_xyz.insert(s.path_xyz.end(), p.p, p.p + 3);
    s.path_motion.push_back(p.motion);
  }
  // Each quantity with a value somewhere, coded in a byte per point over its range.
  for (std::size_t q = 0; q < quantities_.size(); ++q) {
    double lo = INFINITY, hi = -INFINITY;
    for (const PathPoint& p : path_) {
      if (!std::isnan(p.values[q])) {
        lo = std::min(lo, static_cast<double>(p.values[q]));
        hi = std::max(hi, static_cast<double>(p.values[q]));
      }
    }
    if (!(lo <= hi))
      continue;
    std::vector<std::uint8_t> codes;
    codes.reserve(path_.size());
    for (const PathPoint& p : path_) {
      if (std::isnan(p.values[q])) {
        codes.push_back(255);
      } else {
        const double t = hi > lo ? (p.values[q] - lo) / (hi - lo) : 0.5;
        codes.push_back(static_cast<std::uint8_t>(std::lround(std::clamp(t, 0.0, 1.0) * 254.0)));
      }
    }
    s.quantities.push_back(quantities_[q]);
    s.path_value_codes.push_back(std::move(codes));
    s.value_range.push_back({lo, hi});
  }
  return s;
}

}  // namespace redpost::report
