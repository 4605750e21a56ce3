#include "redpost/post/session.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>

#include "cl/arc_chords.hpp"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"

namespace redpost {

namespace {

std::string joint_label(const Cell& cell, int i) {
  if (i < 0)
    return "?";
  const Joint& j = cell.joint(i);
  return j.axis.mapped() ? "'" + j.name + "' (" + axis_name(j.axis) + ")" : "'" + j.name + "'";
}

// A joint value as the robot programmer knows it: in controller units where the joint has an
// axis (A2 -90 deg rather than theta_2 -1.5708 rad), in DH degrees or mm otherwise.
std::string in_units(const Joint& j, double v) {
  const double shown = j.axis.mapped()                  ? to_axis_value(j, v)
                       : j.type == JointType::prismatic ? v
                                                        : rad_to_deg(v);
  return fmt::format(j.type == JointType::prismatic ? "{:.3f} mm" : "{:.3f} deg", shown);
}

std::string limits_text(const Joint& j) {
  std::string lo = in_units(j, j.lower), hi = in_units(j, j.upper);
  if (j.axis.mapped() && j.axis.sign < 0)
    std::swap(lo, hi);
  return "[" + lo + ", " + hi + "]";
}

// A temporary file renamed into place on commit, removed otherwise.
class PendingFile {
 public:
  PendingFile() = default;
  explicit PendingFile(std::string path) : path_(std::move(path)), temp_(temporary_path(path_)) {
    file_ = std::fopen(temp_.c_str(), "wb");
    if (!file_) {
      throw Error(ErrorCode::io, std::string("cannot create the file: ") + std::strerror(errno),
                  SourceLocation{path_, 0, 0});
    }
  }
  ~PendingFile() {
    if (file_) {
      std::fclose(file_);
      std::remove(temp_.c_str());
    }
  }
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  bool open() const { return file_ != nullptr; }
  void write(const fmt::memory_buffer& b) {
    if (std::fwrite(b.data(), 1, b.size(), file_) != b.size()) {
      throw Error(ErrorCode::io, std::string("write failed: ") + std::strerror(errno),
                  SourceLocation{path_, 0, 0});
    }
  }
  void commit() {
    std::FILE* file = file_;
    file_ = nullptr;
    try {
      flush_to_disk(file, path_);
    } catch (...) {
      std::fclose(file);
      std::remove(temp_.c_str());
      throw;
    }
    const bool closed = std::fclose(file) == 0;
    if (!closed || std::rename(temp_.c_str(), path_.c_str()) != 0) {
      const int err = errno;
      std::remove(temp_.c_str());
      throw Error(ErrorCode::io, std::string("cannot complete the file: ") + std::strerror(err),
                  SourceLocation{path_, 0, 0});
    }
    sync_directory(std::filesystem::path(path_).parent_path().string());
  }

 private:
  std::string path_, temp_;
  std::FILE* file_ = nullptr;
};

}  // namespace

struct PostSession::Impl {
  const Cell& cell;
  PostOptions o;
  Tracker tracker;
  KrlWriter writer;
  ArmStatusModel arm;
  std::unique_ptr<PendingFile> csv;
  fmt::memory_buffer line;

  bool started = false;
  bool next_rapid = false;
  double feed_mm_per_min = std::numeric_limits<double>::quiet_NaN();
  bool feed_warned = false;
  TcpTarget last_target;
  // The last move's point and tool axis in CL coordinates: the start of a circular move.
  Eigen::Vector3d last_cl_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_cl_axis = Eigen::Vector3d::UnitZ();
  PoseResult last;
  KinematicsData data;
  JointVector q_physical;
  int spin_last = -1;  // chain index of a final pure-spin virtual joint (see physical_tcp)
  PostSummary summary;

  Impl(const Cell& c, const KrlTemplateSet& templates, const PostOptions& options)
      : cell(c),
        o(options),
        tracker(c, options.tracker),
        writer(templates, options.program),
        arm(make_arm_status_model(c)),
        spin_last(last_pure_spin(c)) {
    summary.joints.assign(static_cast<size_t>(c.size()), JointRange{});
    for (JointRange& r : summary.joints) {
      r.lowest = r.margin_lower = r.margin_upper = std::numeric_limits<double>::infinity();
      r.highest = -std::numeric_limits<double>::infinity();
    }
    if (!o.joints_csv_path.empty()) {
      csv = std::make_unique<PendingFile>(o.joints_csv_path);
      line.clear();
      fmt::format_to(std::back_inserter(line), "pose,cl_line");
      for (int i = 0; i < c.size(); ++i)
        fmt::format_to(std::back_inserter(line), ",{}", c.joint(i).name);
      for (int i = 0; i < c.size(); ++i) {
        if (c.joint(i).axis.mapped()) {
          fmt::format_to(std::back_inserter(line), ",{}", axis_name(c.joint(i).axis));
        }
      }
      line.push_back('\n');
      csv->write(line);
    }
  }

  [[noreturn]] void fail(const PoseResult& r, int cl_line, const char* what) {
    std::string msg = fmt::format("pose {} ({}): ", summary.poses + 1, what);
    switch (r.status) {
      case PoseStatus::unreachable:
        msg += fmt::format(
            "the target cannot be reached: {:.4g} mm and {:.4g} deg from it after {} iterations. "
            "Check where the part is placed in the cell (--placement) and that the toolpath fits "
            "the cell's work space",
            r.position_error_mm, rad_to_deg(r.orientation_error_rad), r.iterations);
        throw Error(ErrorCode::unreachable, msg, SourceLocation{o.source_name, cl_line, 0});
      case PoseStatus::joint_limit: {
        const int i = r.offending_joint;
        msg += fmt::format(
            "joint {} would have to leave its limits {}. Move the part, or let the "
            "redundant axes help (are track and table free?)",
            joint_label(cell, i), i >= 0 ? limits_text(cell.joint(i)) : "[?]");
        throw Error(ErrorCode::joint_limit, msg, SourceLocation{o.source_name, cl_line, 0});
      }
      case PoseStatus::joint_jump: {
        const int i = r.offending_joint;
        msg += fmt::format(
            "joint {} would jump by {} between two consecutive poses (a wrist flip or a "
            "discontinuous toolpath). Smooth the tool axis or split the operation",
            joint_label(cell, i),
            i >= 0 ? (cell.joint(i).type == JointType::prismatic
                          ? fmt::format("{:.3f} mm", r.offending_step)
                          : fmt::format("{:.3f} deg", rad_to_deg(r.offending_step)))
                   : "?");
        throw Error(ErrorCode::unreachable, msg, SourceLocation{o.source_name, cl_line, 0});
      }
      case PoseStatus::converged:
        break;
    }
    throw Error(ErrorCode::internal, "fail() on a converged pose");
  }

  void record(const PoseResult& r, int cl_line) {
    ++summary.poses;
    last = r;
    if (r.inv_condition < summary.lowest_inv_condition) {
      summary.lowest_inv_condition = r.inv_condition;
      summary.lowest_inv_condition_line = cl_line;
    }
    for (int i = 0; i < cell.size(); ++i) {
      JointRange& jr = summary.joints[static_cast<size_t>(i)];
      const double q = r.q[i];
      jr.lowest = std::min(jr.lowest, q);
      jr.highest = std::max(jr.highest, q);
      jr.margin_lower = std::min(jr.margin_lower, q - cell.joint(i).lower);
      jr.margin_upper = std::min(jr.margin_upper, cell.joint(i).upper - q);
    }
  }

  void emit(KrlMotionKind kind, const JointVector& q, int cl_line) {
    // Never write a posture outside the limits: the tracker guarantees it, this makes sure.
    if (!within_limits(cell, q)) {
      throw Error(ErrorCode::internal, "a posture outside the joint limits reached the writer",
                  SourceLocation{o.source_name, cl_line, 0});
    }
    KrlMotion m;
    m.kind = kind;
    m.axes = to_controller_axes(cell, q);
    m.cl_line = cl_line;
    m.T_base_tcp = o.T_B_base.inverse() * physical_tcp(q);
    m.status_turn = status_turn(cell, arm, q);
    writer.motion(m);
    ++summary.motions;
    if (o.on_motion)
      observe(m, q);
    if (csv) {
      line.clear();
      fmt::format_to(std::back_inserter(line), "{},{}", summary.motions, cl_line);
      for (int i = 0; i < cell.size(); ++i)
        fmt::format_to(std::back_inserter(line), ",{:.9f}", q[i]);
      for (int i = 0; i < cell.size(); ++i) {
        if (cell.joint(i).axis.mapped()) {
          fmt::format_to(std::back_inserter(line), ",{:.6f}", to_axis_value(cell.joint(i), q[i]));
        }
      }
      line.push_back('\n');
      csv->write(line);
    }
  }

  void observe(const KrlMotion& m, const JointVector& q) {
    MotionSample s;
    s.index = summary.motions;
    s.kind = m.kind;
    s.cl_line = m.cl_line;
    s.q = &q;
    s.axes = &m.axes;
    s.inv_condition = last.inv_condition;
    s.iterations = last.iterations;
    if (m.kind == KrlMotionKind::lin)
      s.feed_mm_per_min = feed_mm_per_min;
    // {base} -> {B} -> part: the TCP the controller is sent, in the CL frame.
    s.p_part_mm = o.T_B_part.inverse() * (o.T_B_base * m.T_base_tcp.translation());
    o.on_motion(s);
  }

  // The physical TCP is the chain's TCP with every virtual joint at 0: the controller's $TOOL
  // knows nothing of the free spin. When the only virtual joint ends the chain with a pure
  // Rz(theta) Tz(d) link (alpha = 0, a = 0, no tool frame after it), that is the tracked TCP
  // turned back by -theta about its own z: no second forward kinematics per motion.
  Isometry physical_tcp(const JointVector& q) {
    if (spin_last >= 0) {
      Isometry T = tracker.tcp_pose_at_q();
      T.linear() = T.linear() * Eigen::AngleAxisd(-q[spin_last], Eigen::Vector3d::UnitZ());
      return T;
    }
    q_physical = q;
    for (int i = 0; i < cell.size(); ++i) {
      if (cell.joint(i).type == JointType::virtual_spin)
        q_physical[i] = 0.0;
    }
    forward_kinematics(cell, q_physical, data);
    return data.T_B_tcp;
  }

  static int last_pure_spin(const Cell& c) {
    int virtuals = 0;
    for (int i = 0; i < c.size(); ++i)
      virtuals += c.joint(i).type == JointType::virtual_spin;
    const int last = c.size() - 1;
    const Joint& j = c.joint(last);
    const bool pure = virtuals == 1 && j.type == JointType::virtual_spin && j.alpha_rad == 0.0 &&
                      j.a_mm == 0.0 && !c.has_tcp_frame;
    return pure ? last : -1;
  }

  TcpTarget target_in_B(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line) {
    const double norm = axis.norm();
    if (!p_mm.allFinite() || !std::isfinite(norm)) {
      throw Error(ErrorCode::bad_input, "a move with a coordinate that is not a finite number",
                  SourceLocation{o.source_name, cl_line, 0});
    }
    if (!(norm > 1e-9)) {
      throw Error(ErrorCode::bad_input, "a move with a tool axis of zero length",
                  SourceLocation{o.source_name, cl_line, 0});
    }
    return TcpTarget::axis(o.T_B_part * p_mm, o.T_B_part.linear() * (axis / norm));
  }

  void move(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line) {
    const TcpTarget target = target_in_B(p_mm, axis, cl_line);
    const bool rapid = next_rapid;
    next_rapid = false;
    if (!started) {
      // The first pose, far from home: several starts, the solution nearest home, and a PTP.
      const PoseResult r = tracker.solve_first_pose(target);
      if (r.status != PoseStatus::converged)
        fail(r, cl_line, "the first pose of the path");
      tracker.reset(r.q);
      started = true;
      record(r, cl_line);
      emit(KrlMotionKind::ptp_axes, r.q, cl_line);
      last_target = target;
      remember_cl(p_mm, axis);
      return;
    }
    if (!rapid) {
      if (std::isnan(feed_mm_per_min)) {
        feed_mm_per_min = o.default_feed_mm_per_min;
        if (!feed_warned) {
          summary.warnings.push_back(
              fmt::format("{}:{}: a cutting move before any FEDRAT; using {} mm/min", o.source_name,
                          cl_line, o.default_feed_mm_per_min));
          feed_warned = true;
        }
      }
      writer.velocity(feed_mm_per_min / 60000.0);
    }
    // Long moves in steps, so that the redundancy is resolved continuously along them.
    const double length = (target.p_B_mm - last_target.p_B_mm).norm();
    const double turn = std::acos(std::clamp(target.z_B.dot(last_target.z_B), -1.0, 1.0));
    const int steps =
        std::max(1, static_cast<int>(std::ceil(
                        std::max(length / o.max_step_mm, rad_to_deg(turn) / o.max_step_axis_deg))));
    for (int s = 1; s <= steps; ++s) {
      TcpTarget step = target;
      if (s < steps) {
        const double t = static_cast<double>(s) / steps;
        step.p_B_mm = (1.0 - t) * last_target.p_B_mm + t * target.p_B_mm;
        const Eigen::Quaterniond turn_all =
            Eigen::Quaterniond::FromTwoVectors(last_target.z_B, target.z_B);
        step.z_B =
            (Eigen::Quaterniond::Identity().slerp(t, turn_all) * last_target.z_B).normalized();
      }
      PoseResult r = tracker.track(step);
      if (r.status != PoseStatus::converged && rapid) {
        // A rapid traverse goes joint-interpolated (PTP): it need not follow the straight line,
        // so its end may be solved directly from the current posture.
        r = tracker.solve_first_pose(target);
        if (r.status == PoseStatus::converged) {
          tracker.reset(r.q);
          summary.warnings.push_back(fmt::format(
              "{}:{}: the straight line of this rapid traverse is not trackable; its end was "
              "solved directly and is reached by PTP",
              o.source_name, cl_line));
          record(r, cl_line);
          break;
        }
      }
      if (r.status != PoseStatus::converged)
        fail(r, cl_line, rapid ? "rapid" : "cutting move");
      record(r, cl_line);
    }
    emit(rapid ? KrlMotionKind::rapid : KrlMotionKind::lin, tracker.q(), cl_line);
    last_target = target;
    remember_cl(p_mm, axis);
  }

  void remember_cl(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis) {
    last_cl_point = p_mm;
    last_cl_axis = axis.normalized();
  }

  void circular_move(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double radius_mm,
                     const Eigen::Vector3d& p_mm, const Eigen::Vector3d& tool_axis, int cl_line) {
    const SourceLocation at{o.source_name, cl_line, 0};
    if (!centre.allFinite() || !axis.allFinite() || !std::isfinite(radius_mm) ||
        !p_mm.allFinite() || !tool_axis.allFinite()) {
      throw Error(ErrorCode::bad_input,
                  "a circular move with a coordinate that is not a finite number", at);
    }
    const double norm = axis.norm();
    if (!(norm > 1e-9))
      throw Error(ErrorCode::bad_input, "a circular move with an axis of zero length", at);
    if (radius_mm < 0.0) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("a circular move with a negative radius {} mm", radius_mm), at);
    }
    if (!(tool_axis.norm() > 1e-9))
      throw Error(ErrorCode::bad_input, "a move with a tool axis of zero length", at);
    if (!started) {
      throw Error(ErrorCode::bad_input,
                  "a circular move needs a start point, but no move came before it", at);
    }
    detail::ArcWording wording;
    wording.radius_from = "the circular move";
    const detail::ArcBuild built =
        detail::make_arc_chords(last_cl_point, centre, axis / norm, radius_mm, p_mm,
                                o.arc_point_tolerance_mm, o.chordal_tolerance_mm, wording);
    if (built.problem != detail::ArcProblem::none)
      throw Error(ErrorCode::bad_input, built.message, at);
    // Every chord of a rapid arc is rapid, as the reader marks them.
    const bool rapid = next_rapid;
    const Eigen::Vector3d chord_axis = last_cl_axis;
    for (long k = 1; k <= built.arc.chords; ++k) {
      next_rapid = rapid;
      move(built.arc.point(k), k == built.arc.chords ? tool_axis : chord_axis, cl_line);
    }
  }
};

PostSession::PostSession(const Cell& cell, const KrlTemplateSet& templates,
                         const PostOptions& options)
    : impl_(std::make_unique<Impl>(cell, templates, options)) {}

PostSession::~PostSession() = default;

void PostSession::handle(const ClEvent& e) {
  switch (e.kind) {
    case ClEventKind::part_name:
      comment("part " + e.text);
      break;
    case ClEventKind::tool_change:
      tool_change(e.tool_number, e.text, e.tool_diameter_mm, e.tool_length_mm);
      break;
    case ClEventKind::spindle:
      spindle(e.value, e.direction);
      break;
    case ClEventKind::feed:
      feed(e.value);
      break;
    case ClEventKind::rapid:
      rapid();
      break;
    case ClEventKind::move:
      if (e.rapid)
        rapid();
      move(e.p_mm, e.tool_axis, e.line);
      break;
    case ClEventKind::coolant:
      coolant(e.flag, e.text);
      break;
    case ClEventKind::operation_start:
      operation_start(e.text);
      break;
    case ClEventKind::operation_end:
      operation_end();
      break;
    case ClEventKind::comment:
      comment(e.text);
      break;
    case ClEventKind::literal:
      literal(e.text);
      break;
    case ClEventKind::unknown_word:
    case ClEventKind::end_of_program:
      break;
  }
}

void PostSession::tool_change(int number, const std::string& name, double, double) {
  impl_->writer.tool_change(number, name);
}

void PostSession::spindle(double rpm, SpindleDirection direction) {
  if (!std::isfinite(rpm) || rpm < 0.0) {
    throw Error(ErrorCode::bad_input, fmt::format("spindle speed {} rpm is not valid", rpm));
  }
  impl_->writer.spindle(direction == SpindleDirection::off ? 0.0 : rpm,
                        direction != SpindleDirection::counter_clockwise);
}

void PostSession::feed(double mm_per_min) {
  if (!std::isfinite(mm_per_min) || !(mm_per_min > 0.0)) {
    throw Error(ErrorCode::bad_input, fmt::format("feed {} mm/min is not valid", mm_per_min));
  }
  impl_->feed_mm_per_min = mm_per_min;
}

void PostSession::rapid() {
  impl_->next_rapid = true;
}

void PostSession::move(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& tool_axis, int cl_line) {
  impl_->move(p_mm, tool_axis, cl_line);
}

void PostSession::circular_move(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis,
                                double radius_mm, const Eigen::Vector3d& p_mm,
                                const Eigen::Vector3d& tool_axis, int cl_line) {
  impl_->circular_move(centre, axis, radius_mm, p_mm, tool_axis, cl_line);
}

void PostSession::coolant(bool on, const std::string& mode) {
  impl_->writer.coolant(on, mode);
}
void PostSession::operation_start(const std::string& name) {
  impl_->writer.comment("operation " + name);
}
void PostSession::operation_end() {}
void PostSession::comment(const std::string& text) {
  impl_->writer.comment(text);
}
void PostSession::literal(const std::string& text) {
  impl_->writer.literal(text);
}

const PostSummary& PostSession::finish() {
  Impl& m = *impl_;
  if (!m.started) {
    throw Error(ErrorCode::bad_input, "the toolpath has no move: nothing to write",
                SourceLocation{m.o.source_name, 0, 0});
  }
  // The joints log first: if the program cannot be completed after it, the log is complete and
  // correct, whereas a program without its log would be the worse half to leave behind.
  if (m.csv) {
    m.csv->commit();
    m.csv.reset();  // committed: nothing left to remove, and a second finish() cannot touch it
  }
  m.summary.files = m.writer.finish();
  return m.summary;
}

void PostSession::set_motion_observer(MotionObserver observer) {
  impl_->o.on_motion = std::move(observer);
}

const PoseResult& PostSession::last_pose() const {
  return impl_->last;
}
const PostSummary& PostSession::summary() const {
  return impl_->summary;
}
const Cell& PostSession::cell() const {
  return impl_->cell;
}

}  // namespace redpost
