// A motion as `redpost diff` compares it (krl/diff_pose.hpp).
#include "krl/diff_pose.hpp"

#include <cmath>

#include "krl/text.hpp"

namespace redpost::krl {

namespace {

const char* const kCart[6] = {"X", "Y", "Z", "A", "B", "C"};
const char* const kAxes[12] = {"A1", "A2", "A3", "A4", "A5", "A6",
                               "E1", "E2", "E3", "E4", "E5", "E6"};

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
  h ^= v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  return h * 0xff51afd7ed558ccdULL;
}

std::uint64_t rounded(double v, double grid) {
  if (!std::isfinite(v))
    return 0x7ff8000000000001ULL;
  return static_cast<std::uint64_t>(std::llround(v / grid));
}

bool finite3(const std::array<double, 3>& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Kind of target and position rounded to 0.1 mm (axis targets: axes rounded to 0.1). The key
// only decides which motions are paired; every pair is then compared in full, and motions whose
// keys differ inside a run of mismatches are paired again. The kind of target, not the keyword:
// a template that writes SLIN for LIN must pair each motion with its partner (the keyword is
// then one summarised difference).
std::uint64_t motion_key(const DiffPose& p) {
  std::uint64_t h = p.cartesian ? 1 : p.axis ? 2 : 3;
  if (p.cartesian) {
    for (double c : p.xyz)
      h = mix(h, rounded(c, 0.1));
  } else {
    for (int i = 0; i < 6; ++i)
      h = mix(h, rounded(p.axes[static_cast<size_t>(i)], 0.1));
  }
  return h;
}

}  // namespace

bool DiffPose::on_cartesian_path() const {
  return cartesian && !relative && finite3(xyz);
}

std::uint64_t motion_key_with_cl(const DiffPose& p) {
  return mix(p.key, static_cast<std::uint64_t>(static_cast<std::int64_t>(p.cl_line)));
}

const std::string* PoseCompleter::intern(const std::string& s) {
  const auto it = index_.find(s);
  if (it != index_.end())
    return it->second;
  strings_.push_back(s);
  const std::string* p = &strings_.back();
  index_.emplace(s, p);
  return p;
}

DiffPose PoseCompleter::complete(const KrlMotionRecord& m) {
  DiffPose pose;
  pose.seq = next_seq_++;
  pose.keyword = intern(upper(m.keyword));
  pose.file = intern(m.file);
  pose.line = m.line;
  pose.cl_line = m.cl_line;
  pose.relative = m.relative;
  pose.vel_cp_m_per_s = m.vel_cp_m_per_s;
  pose.apo_cdis_mm = m.apo_cdis_mm;
  pose.ptp_velocity_percent = m.ptp_velocity_percent;
  if (!last_tool_ || *last_tool_ != m.tool)
    last_tool_ = intern(m.tool);
  if (!last_base_ || *last_base_ != m.base)
    last_base_ = intern(m.base);
  pose.tool = last_tool_;
  pose.base = last_base_;

  const auto& v = m.target.values;
  const auto has = [&](int first, int count, const char* const* names) {
    for (int i = first; i < first + count; ++i)
      if (v.count(names[i]))
        return true;
    return false;
  };
  pose.cartesian = has(0, 6, kCart);
  pose.axis = !pose.cartesian && has(0, 6, kAxes);
  if (m.relative) {
    // A relative motion is compared as written: its increments.
    for (int i = 0; i < 6; ++i) {
      const auto it = v.find(kCart[i]);
      (i < 3 ? pose.xyz[static_cast<size_t>(i)] : pose.abc[static_cast<size_t>(i - 3)]) =
          it == v.end() ? 0.0 : it->second;
    }
    for (int i = 0; i < 12; ++i) {
      const auto it = v.find(kAxes[i]);
      if (it != v.end())
        pose.axes[static_cast<size_t>(i)] = it->second;
    }
  } else {
    if (pose.cartesian) {
      for (int i = 0; i < 6; ++i) {
        const auto it = v.find(kCart[i]);
        if (it != v.end())
          cart_[static_cast<size_t>(i)] = it->second;
      }
      for (size_t i = 0; i < 3; ++i) {
        pose.xyz[i] = cart_[i];
        pose.abc[i] = cart_[i + 3];
      }
    }
    for (int i = 0; i < 12; ++i) {
      if (i < 6 && !pose.axis)
        continue;
      const auto it = v.find(kAxes[i]);
      if (it != v.end())
        axes_[static_cast<size_t>(i)] = it->second;
      pose.axes[static_cast<size_t>(i)] = axes_[static_cast<size_t>(i)];
    }
  }
  if (m.target.status)
    pose.status = static_cast<std::int32_t>(*m.target.status);
  if (m.target.turn)
    pose.turn = static_cast<std::int32_t>(*m.target.turn);
  if (m.aux) {
    pose.has_aux = true;
    for (int i = 0; i < 3; ++i) {
      const auto it = m.aux->values.find(kCart[i]);
      pose.aux[static_cast<size_t>(i)] = it == m.aux->values.end() ? kNoValue : it->second;
    }
  }
  pose.key = motion_key(pose);
  return pose;
}

}  // namespace redpost::krl
