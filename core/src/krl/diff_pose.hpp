// A motion as `redpost diff` compares it (docs/krl-diff.md): the target made complete, the
// settings in force, where it is written, and the key it is aligned by. Small and free of maps,
// so that a window of them is cheap to hold; its strings are interned by the side it was read
// from (PoseCompleter), which keeps them while the diff runs.
//
// Internal to redpost::core; not installed.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <string>
#include <unordered_map>

#include "redpost/krl/reader.hpp"

namespace redpost::krl {

inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();
inline constexpr std::int32_t kNoInt =
    std::numeric_limits<std::int32_t>::min();  // S, T not written

struct DiffPose {
  std::uint64_t key = 0;  // kind of target and rounded position (motion_key); no CL line
  std::uint64_t seq = 0;  // index in its program's motions, from 0
  std::array<double, 3> xyz{kNoValue, kNoValue, kNoValue};
  std::array<double, 3> abc{kNoValue, kNoValue, kNoValue};
  std::array<double, 3> aux{kNoValue, kNoValue, kNoValue};  // CIRC's auxiliary point
  std::array<double, 12> axes{kNoValue, kNoValue, kNoValue, kNoValue, kNoValue, kNoValue,
                              kNoValue, kNoValue, kNoValue, kNoValue, kNoValue, kNoValue};
  double vel_cp_m_per_s = 0.0;
  double apo_cdis_mm = -1.0;
  double ptp_velocity_percent = -1.0;
  const std::string* file = nullptr;  // interned by the side's PoseCompleter
  const std::string* keyword = nullptr;
  const std::string* tool = nullptr;
  const std::string* base = nullptr;
  std::int32_t line = 0;
  std::int32_t cl_line = 0;
  std::int32_t status = kNoInt, turn = kNoInt;
  bool cartesian = false;  // an X/Y/Z/A/B/C target
  bool axis = false;       // an A1..A6 target
  bool relative = false;   // LIN_REL, PTP_REL: compared as written
  bool has_aux = false;

  // A point of the Cartesian path (the path comparison): a finite absolute Cartesian target.
  bool on_cartesian_path() const;
};

// Turns the records of one program, in order, into DiffPoses: a partial aggregate (LIN {X 110})
// keeps the other fields of the previous target of its kind, as the controller takes them from
// the current position. Owns the strings the poses point at (their addresses never move).
class PoseCompleter {
 public:
  DiffPose complete(const KrlMotionRecord& m);
  std::uint64_t count() const { return next_seq_; }

 private:
  const std::string* intern(const std::string& s);

  std::array<double, 6> cart_{kNoValue, kNoValue, kNoValue, kNoValue, kNoValue, kNoValue};
  std::array<double, 12> axes_{kNoValue, kNoValue, kNoValue, kNoValue, kNoValue, kNoValue,
                               kNoValue, kNoValue, kNoValue, kNoValue, kNoValue, kNoValue};
  std::uint64_t next_seq_ = 0;
  std::deque<std::string> strings_;
  std::unordered_map<std::string, const std::string*> index_;
  const std::string* last_tool_ = nullptr;  // the settings rarely change: skip the lookup
  const std::string* last_base_ = nullptr;
};

// The key a motion is aligned by, with the CL line mixed in when aligning by CL lines.
std::uint64_t motion_key_with_cl(const DiffPose& p);

}  // namespace redpost::krl
