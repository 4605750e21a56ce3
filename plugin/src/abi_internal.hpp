// The C ABI's internals shared by its sources: abi.cpp (sessions) and abi_reader.cpp (the CL
// reader, and reader events sent to a session). The error plumbing (guard: every C++ exception
// becomes an rp_status and a message) and the handle types behind redpost.h.
//
// Internal to libredpost; not installed.
#pragma once

#include <chrono>
#include <cstring>
#include <fstream>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "redpost.h"
#include "redpost/cl/reader.hpp"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/error.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/post/session.hpp"
#include "report/convert_report.hpp"

namespace redpost::abi {

using redpost::ErrorCode;

// rp_last_error(NULL): the last failure of rp_open, rp_reader_open or a NULL handle, per thread
// (hosts may open sessions on several threads at once).
inline thread_local std::string t_error;

inline rp_status status_of(ErrorCode code) {
  switch (code) {
    case ErrorCode::bad_input:
      return RP_ERR_BAD_INPUT;
    case ErrorCode::io:
      return RP_ERR_IO;
    case ErrorCode::unreachable:
      return RP_ERR_UNREACHABLE;
    case ErrorCode::joint_limit:
      return RP_ERR_JOINT_LIMIT;
    case ErrorCode::internal:
      return RP_ERR_INTERNAL;
  }
  return RP_ERR_INTERNAL;
}

// A failure the ABI itself detects (NULL argument, wrong state), carried like an Error.
struct AbiError {
  rp_status status;
  std::string message;
};

// Runs f(), returning RP_OK, or the status of what it threw with `prefix` + message in `error`.
template <class F>
rp_status guard(std::string& error, const std::string& prefix, F&& f) noexcept {
  try {
    try {
      f();
      return RP_OK;
    } catch (const AbiError& e) {
      error = prefix + e.message;
      return e.status;
    } catch (const redpost::Error& e) {
      error = prefix + e.what();
      return status_of(e.code());
    } catch (const std::bad_alloc&) {
      error = prefix + "out of memory";
      return RP_ERR_INTERNAL;
    } catch (const std::exception& e) {
      error = prefix + "internal error: " + e.what();
      return RP_ERR_INTERNAL;
    } catch (...) {
      error = prefix + "internal error: an unknown exception";
      return RP_ERR_INTERNAL;
    }
  } catch (...) {
    // Building the message itself failed (out of memory): the status still gets through.
    return RP_ERR_INTERNAL;
  }
}

inline rp_status null_handle(const char* what) noexcept {
  try {
    t_error = std::string(what) + " is NULL";
  } catch (...) {
  }
  return RP_ERR_NULL;
}

inline std::string required(const char* s, const char* what) {
  if (!s)
    throw AbiError{RP_ERR_NULL, std::string(what) + " is NULL"};
  return s;
}

// The shipped definitions (abi.cpp): installed beside the library, or the source tree's.
std::string definitions_dir();
// A template set: a file, or the name of a shipped set; NULL: krc4_lin (abi.cpp).
std::string template_set_path(const char* given);

inline Eigen::Vector3d vec(double x, double y, double z) {
  return Eigen::Vector3d(x, y, z);
}

// The motion observer and the report (abi_report.cpp).
void install_observer(rp_session* session);
// rp_open: the report's target checked and its recorder made, when options ask for one.
void open_report(rp_session* session, const rp_options& o);
// After the program is prepared: the report written to its temporary (nothing without one).
void prepare_report(rp_session* session);
// After the program's rename: the report's.
void commit_report(rp_session* session);

// A query struct the host hands in (rp_timing, rp_cell_info, ...): its struct_size must be set
// and not beyond this library's struct.
template <class T>
void check_struct_size(const T* given, const char* call, const char* type) {
  if (given->struct_size == 0 || given->struct_size > sizeof(T)) {
    throw AbiError{RP_ERR_BAD_INPUT, std::string(call) + ": struct_size is " +
                                         std::to_string(given->struct_size) +
                                         "; set it to sizeof(" + type + ")"};
  }
}

// Writes `out` into the host's struct: a host built against an older, shorter struct gets its
// own fields only, and its struct_size stays what it set.
template <class T>
void copy_sized(T* to, T out) {
  out.struct_size = to->struct_size;
  std::memcpy(to, &out, to->struct_size);
}

// "A1".."E6" or "none" as a static string: valid whatever happens to the session.
inline const char* static_axis_name(const redpost::ControllerAxis& axis) {
  static const char* const kAxisNames[] = {"A1", "A2", "A3", "A4", "A5", "A6",
                                           "E1", "E2", "E3", "E4", "E5", "E6"};
  if (!axis.mapped() || axis.number < 1 || axis.number > 6)
    return "none";
  return kAxisNames[(axis.kind == redpost::AxisKind::external ? 6 : 0) + axis.number - 1];
}

struct Pipeline;

// The largest NURBS a call may give (knots or control points): far beyond any CAM output, and
// a bound on what a host's bad count makes the library read.
inline constexpr int kMaxNurbsValues = 1'000'000;

// An rp_cycle_params (of the host's size) into the cycle event's fields.
inline void cycle_from(const rp_cycle_params& given, redpost::ClEvent& e) {
  check_struct_size(&given, "the cycle", "rp_cycle_params");
  rp_cycle_params p;
  rp_cycle_params_init(&p);
  std::memcpy(&p, &given, given.struct_size);
  redpost::ClCycle& c = e.cycle;
  c.deep = p.peck != 0;
  c.depth_mm = p.depth_mm;
  c.clearance_mm = p.clearance_mm;
  c.retract_mm = p.retract_mm;
  c.feed_mm_per_min = p.feed_mm_per_min;
  c.dwell_s = p.dwell_s;
  c.first_peck_mm = p.first_peck_mm;
  c.next_peck_mm = p.next_peck_mm;
  e.text = p.name ? p.name : "CYCLE/DRILL";
}

// The knots and the x, y, z, w of each control point into the NURBS event's fields.
inline void nurbs_from(const double* knots, int knot_count, const double* points, int point_count,
                       redpost::ClEvent& e) {
  if (knot_count < 0 || point_count < 0 || knot_count > kMaxNurbsValues ||
      point_count > kMaxNurbsValues) {
    throw AbiError{RP_ERR_BAD_INPUT, "a NURBS with " + std::to_string(knot_count) + " knots and " +
                                         std::to_string(point_count) + " control points: at most " +
                                         std::to_string(kMaxNurbsValues) + " of each"};
  }
  if ((knot_count > 0 && !knots) || (point_count > 0 && !points))
    throw AbiError{RP_ERR_NULL, "the NURBS's knots or points are NULL"};
  e.nurbs_knots.assign(knots, knots + knot_count);
  e.nurbs_points.resize(static_cast<std::size_t>(point_count));
  for (int i = 0; i < point_count; ++i) {
    const double* q = points + 4 * i;
    e.nurbs_points[static_cast<std::size_t>(i)] = {q[0], q[1], q[2], q[3]};
  }
}

// The value a host passed for a C enum, read as the int it is: a C host may pass any int, and in
// C++ loading an enum with a value outside its range is undefined (UBSan reports it).
template <class E>
int enum_value(const E& e) {
  static_assert(sizeof(E) == sizeof(int), "a C enum is an int");
  int v = 0;
  std::memcpy(&v, &e, sizeof v);
  return v;
}

inline redpost::TextKind text_kind_of(const rp_text_kind& kind) {
  switch (enum_value(kind)) {
    case RP_TEXT_INSERT:
      return redpost::TextKind::insert;
    case RP_TEXT_PPRINT:
      return redpost::TextKind::pprint;
    case RP_TEXT_MESSAGE:
      return redpost::TextKind::message;
    default:
      break;
  }
  throw AbiError{RP_ERR_BAD_INPUT, "text kind " + std::to_string(enum_value(kind)) +
                                       " is not one of RP_TEXT_INSERT, _PPRINT, _MESSAGE"};
}

}  // namespace redpost::abi

struct rp_session {
  // prepared: rp_prepare completed the files; only queries and rp_close may follow.
  enum class State { open, prepared, failed, closed };

  // The cell and templates outlive the PostSession, which holds references to them.
  redpost::Cell cell;
  redpost::KrlTemplateSet templates;
  redpost::Isometry T_B_part = redpost::Isometry::Identity();  // the CL frame in {B}
  std::unique_ptr<redpost::PostSession> post;
  State state = State::open;
  long events = 0;  // events sent so far, refused ones included
  bool line_set = false;
  int line = 0;
  std::string failure;  // the message of the event that failed the session
  int error_line = 0;   // the CL line (or event number) the last error names; 0: none
  mutable std::string error;
  // Kept when the PostSession is destroyed (a failed close) so the diagnostics stay readable.
  std::optional<redpost::PostSummary> summary_kept;
  std::optional<redpost::PoseResult> pose_kept;
  double conditioning_threshold = 0.0;     // the tracker's, for rp_motion
  std::vector<std::string> host_warnings;  // rp_warn's, listed before the session's own
  // The host's observer, and the report (rp_options.report_path), both fed by one observer.
  rp_motion_observer host_observer = nullptr;
  void* host_user = nullptr;
  std::string source, cell_path, program;  // as given, for the report
  std::chrono::steady_clock::time_point opened = std::chrono::steady_clock::now();
  std::string report_path;
  std::unique_ptr<redpost::run_report::ConvertReport> report;
  std::optional<redpost::PreparedTexts> report_file;

  // Warning number index: the host's, then the session's; NULL past the end.
  const char* warning(std::size_t index) const {
    if (index < host_warnings.size())
      return host_warnings[index].c_str();
    const std::vector<std::string>& w = summary().warnings;
    index -= host_warnings.size();
    return index < w.size() ? w[index].c_str() : nullptr;
  }

  // Both wait for the pipeline's thread (if any) to have tracked every event sent.
  const redpost::PostSummary& summary() const {
    sync();
    return post ? post->summary() : *summary_kept;
  }
  const redpost::PoseResult& pose() const {
    sync();
    return post ? post->last_pose() : *pose_kept;
  }

  // The pipeline (rp_options.pipeline, abi_pipeline.cpp): the events are tracked on a thread of
  // the session's own, in order, while the host makes the next ones.
  std::unique_ptr<redpost::abi::Pipeline> pipeline;  // the last member: its thread stops first
  rp_session();
  ~rp_session();  // stops the pipeline's thread before anything it uses goes
  rp_session(const rp_session&) = delete;
  rp_session& operator=(const rp_session&) = delete;
  void start_pipeline();
  // An event into the session: tracked at once, or expanded and reduced here and queued for
  // the pipeline's thread.
  void submit(redpost::ClEvent&& e);
  std::vector<redpost::PostSession::FrontItem> front_items;  // submit()'s scratch
  // Waits until the pipeline's thread has tracked every event queued (nothing without one).
  void sync() const;
  // A failure of the pipeline's thread, made the session's: its status (RP_OK: none).
  rp_status take_pipeline_failure();

  int current_line() const { return line_set ? line : static_cast<int>(events); }

  // Dropping the PostSession removes its temporary files; the diagnostics are copied first.
  void abandon() {
    report_file.reset();  // removes the report's temporary
    if (!post)
      return;
    summary_kept = post->summary();
    pose_kept = post->last_pose();
    post.reset();
  }

  // Runs f(), noting the line of the Error it throws (under the plan it may be an earlier
  // event's, deferred until now).
  template <class F>
  void run_noting_line(F&& f) {
    try {
      f();
    } catch (const redpost::Error& e) {
      error_line = e.where().line;
      throw;
    }
  }

  // One event: counted, refused unless open, failing the session if it throws. `at_line` is
  // the CL line the event comes from (rp_session_event: the reader's); -1: the line of
  // rp_set_line, if any. An argument the ABI refuses is named at that line, as the core names
  // what it refuses (docs/c-abi.md, "Messages").
  template <class F>
  rp_status event(F&& f) noexcept {
    return event_at(-1, std::forward<F>(f));
  }
  template <class F>
  rp_status event_at(int at_line, F&& f) noexcept {
    // An earlier event failed on the pipeline's thread: this call tells it.
    if (pipeline && state == State::open) {
      if (const rp_status failed = take_pipeline_failure(); failed != RP_OK)
        return failed;
    }
    ++events;
    std::string prefix;
    try {
      prefix = "event " + std::to_string(events) + ": ";
    } catch (...) {
      return RP_ERR_INTERNAL;
    }
    const rp_status s = redpost::abi::guard(error, prefix, [&] {
      if (state == State::failed) {
        throw redpost::abi::AbiError{RP_ERR_STATE,
                                     "refused because the session failed at " + failure};
      }
      if (state == State::closed)
        throw redpost::abi::AbiError{RP_ERR_STATE, "refused because the session is closed"};
      if (state == State::prepared) {
        throw redpost::abi::AbiError{
            RP_ERR_STATE,
            "refused because the session is prepared (rp_prepare): only rp_close "
            "or rp_free may follow"};
      }
      const int where = at_line >= 0 ? at_line : (line_set ? line : 0);
      try {
        run_noting_line(f);
      } catch (redpost::abi::AbiError& refused) {
        if (where > 0) {
          error_line = where;
          refused.message = source + ":" + std::to_string(where) + ": " + refused.message;
        }
        throw;
      }
    });
    if (s != RP_OK && state == State::open) {
      state = State::failed;
      try {
        failure = error;
      } catch (...) {
      }
    }
    return s;
  }
};

struct rp_reader {
  std::ifstream in;
  std::unique_ptr<redpost::ClReader> reader;
  redpost::ClEvent event;
  bool toolpath_events = false;      // rp_reader_options.toolpath_events
  std::vector<double> nurbs_points;  // the event's control points as x, y, z, w
  std::string error;
  // A reader that failed stays failed: every later rp_reader_next gives this status and the
  // same error, not a clean end of a half-read file.
  rp_status failed = RP_OK;
};
