// The C ABI (redpost.h) over redpost::core's PostSession and ClReader.
//
// Every rp_ function is a C function that must never let a C++ exception out: each body runs in
// guard(), which turns Error into its rp_status and the message, and std::bad_alloc, any other
// std::exception or anything else into RP_ERR_INTERNAL. A session is a small state machine
// (open -> failed | closed) so that misuse gives RP_ERR_STATE instead of undefined behaviour.
#include <dlfcn.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "redpost.h"
#include "redpost/cl/reader.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/output_target.hpp"
#include "redpost/io/temporaries.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/post/session.hpp"

#include "abi_internal.hpp"

namespace redpost::abi {

// The shipped definitions: those installed with this library (PREFIX/share/redpost/definitions)
// when the library is the installed one, else next to a relocated install tree, else the source
// tree's when the library runs from the build tree.
std::string definitions_dir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&rp_version), &info) != 0 && info.dli_fname) {
    const fs::path lib_dir = fs::weakly_canonical(fs::path(info.dli_fname), ec).parent_path();
#ifdef REDPOST_INSTALL_LIBDIR
    const fs::path installed_lib = fs::weakly_canonical(REDPOST_INSTALL_LIBDIR, ec);
    if (!ec && lib_dir == installed_lib && fs::is_directory(REDPOST_INSTALL_DEFINITIONS_DIR, ec))
      return REDPOST_INSTALL_DEFINITIONS_DIR;
#endif
    // PREFIX/lib or PREFIX/lib/<multiarch>.
    for (const fs::path& prefix : {lib_dir.parent_path(), lib_dir.parent_path().parent_path()}) {
      const fs::path d = prefix / "share/redpost/definitions";
      if (fs::is_directory(d, ec))
        return d.string();
    }
  }
  return REDPOST_SOURCE_DEFINITIONS_DIR;
}

// A template set: a file, or the name of a shipped set (a bare name without '/' or extension)
// in the definitions' krl/ folder; NULL: krc4_lin.
std::string template_set_path(const char* given) {
  const std::string name = given ? given : "krc4_lin";
  const bool bare = !name.empty() && name.find('/') == std::string::npos &&
                    std::filesystem::path(name).extension().empty();
  return bare ? definitions_dir() + "/krl/" + name + ".xml" : name;
}

// The plan options of rp_options into PostOptions (docs/redundancy.md).
void set_plan_options(const rp_options& o, const Cell& cell, PostOptions& post) {
  if (o.plan != RP_PLAN_GLOBAL && o.plan != RP_PLAN_LOCAL) {
    throw AbiError{RP_ERR_BAD_INPUT,
                   fmt::format("options.plan is {}: use RP_PLAN_GLOBAL or RP_PLAN_LOCAL", o.plan)};
  }
  if (o.plan_preset < RP_PLAN_SMOOTH || o.plan_preset > RP_PLAN_FAST) {
    throw AbiError{RP_ERR_BAD_INPUT,
                   fmt::format("options.plan_preset is {}: use RP_PLAN_SMOOTH, RP_PLAN_STIFF or "
                               "RP_PLAN_FAST",
                               o.plan_preset)};
  }
  if (!std::isfinite(o.keyframe_spacing_mm) || o.keyframe_spacing_mm < 1.0 ||
      o.keyframe_spacing_mm > 1000.0) {
    throw AbiError{RP_ERR_BAD_INPUT, fmt::format("the keyframe spacing must be 1 to 1000 mm, "
                                                 "got {}",
                                                 o.keyframe_spacing_mm)};
  }
  if (o.plan_threads < 0 || o.plan_threads > 256) {
    throw AbiError{
        RP_ERR_BAD_INPUT,
        fmt::format("options.plan_threads is {}: use 0 (one per core) to 256", o.plan_threads)};
  }
  post.plan_threads = o.plan_threads;
  post.plan = o.plan == RP_PLAN_LOCAL ? RedundancyPlan::local : RedundancyPlan::global;
  post.plan_settings = plan_preset(o.plan_preset == RP_PLAN_STIFF  ? PlanPreset::stiff
                                   : o.plan_preset == RP_PLAN_FAST ? PlanPreset::fast
                                                                   : PlanPreset::smooth);
  post.plan_settings.keyframe_spacing_mm = o.keyframe_spacing_mm;
  post.plan_settings.lock_value =
      JointVector::Constant(cell.size(), std::numeric_limits<double>::quiet_NaN());
  // Bits past E6 name no axis: refused rather than ignored (issue 48).
  if (o.lock_mask >> 6 != 0u) {
    throw AbiError{RP_ERR_BAD_INPUT,
                   fmt::format("options.lock_mask is {:#x}: only bits 0 to 5 (E1 to E6) name an "
                               "external axis",
                               o.lock_mask)};
  }
  for (int k = 0; k < 6; ++k) {
    if (!(o.lock_mask & (1u << k)))
      continue;
    int joint = -1;
    for (int i = 0; i < cell.size(); ++i) {
      const ControllerAxis& a = cell.joint(i).axis;
      if (a.kind == AxisKind::external && a.number == k + 1)
        joint = i;
    }
    if (joint < 0) {
      throw AbiError{RP_ERR_BAD_INPUT, fmt::format("E{} is to be held, but the cell maps no "
                                                   "joint to E{}",
                                                   k + 1, k + 1)};
    }
    post.plan_settings.locked.set(static_cast<std::size_t>(joint));
    post.tracker.locked.set(static_cast<std::size_t>(joint));
    const double v = o.lock_value[k];
    if (std::isfinite(v) && post.plan == RedundancyPlan::local) {
      throw AbiError{RP_ERR_BAD_INPUT, fmt::format("E{} = {}: holding an axis at a given value "
                                                   "needs the global plan",
                                                   k + 1, v)};
    }
    if (std::isfinite(v)) {
      const Joint& j = cell.joint(joint);
      const double q = from_axis_value(j, v);
      if (q < j.lower || q > j.upper) {
        throw AbiError{RP_ERR_BAD_INPUT, fmt::format("E{} = {} is outside the limits of joint '{}'",
                                                     k + 1, v, j.name)};
      }
      post.plan_settings.lock_value[joint] = q;
    }
  }
}

// The placement of rp_options (the CL frame in {B}) into PostOptions.
void set_placement(const rp_options& o, PostOptions& post) {
  if (o.has_placement) {
    const double* p = o.placement;
    // x, y, z within the CL reader's coordinate bound; A, B, C within a turn either way. A
    // value beyond them is a typo, and gave the IK a pose it could not even start from.
    static constexpr const char* kNames[6] = {"x", "y", "z", "A", "B", "C"};
    for (int i = 0; i < 6; ++i) {
      const double bound = i < 3 ? 1e7 : 360.0;
      if (!std::isfinite(p[i]) || std::fabs(p[i]) > bound) {
        throw AbiError{RP_ERR_BAD_INPUT,
                       fmt::format("the placement's {} is {:.6g}: it must be a number of {} "
                                   "from -{:g} to {:g} (--placement x,y,z,a,b,c)",
                                   kNames[i], p[i], i < 3 ? "mm" : "degrees", bound, bound)};
      }
    }
    post.T_B_part =
        redpost::frame_from_xyzabc(p[0], p[1], p[2], redpost::KukaAbc{p[3], p[4], p[5]});
  }
}

// The collision options of rp_options into PostOptions (docs/collision.md).
void set_collision_options(const rp_options& o, PostOptions& post) {
  if (o.collision_check != 0 && o.collision_check != 1) {
    throw AbiError{RP_ERR_BAD_INPUT,
                   fmt::format("options.collision_check is {}: use 1 or 0", o.collision_check)};
  }
  if (!std::isfinite(o.collision_margin_mm) || o.collision_margin_mm < 0.0 ||
      o.collision_margin_mm > 1000.0) {
    throw AbiError{RP_ERR_BAD_INPUT,
                   fmt::format("the collision margin must be a number of mm from 0 to 1000, got "
                               "{}",
                               o.collision_margin_mm)};
  }
  if (o.fixture_count < 0 || o.fixture_count > 1000 || (o.fixture_count > 0 && !o.fixture_paths))
    throw AbiError{RP_ERR_BAD_INPUT, "options.fixture_count needs as many fixture_paths"};
  post.collision.check = o.collision_check == 1;
  post.collision.margin_mm = o.collision_margin_mm;
  for (int i = 0; i < o.fixture_count; ++i) {
    if (!o.fixture_paths[i] || !*o.fixture_paths[i])
      throw AbiError{RP_ERR_BAD_INPUT, fmt::format("options.fixture_paths[{}] is empty", i)};
    post.collision.setup.fixtures.emplace_back(o.fixture_paths[i]);
  }
  if (o.part_path)
    post.collision.setup.part = o.part_path;
  if (!post.collision.check && (o.fixture_count > 0 || o.part_path)) {
    throw AbiError{RP_ERR_BAD_INPUT,
                   "fixtures or a part were given but the collision check is off "
                   "(options.collision_check 0)"};
  }
}

// The deflection options of rp_options into PostOptions (docs/deflection.md).
void set_deflection_options(const rp_options& o, PostOptions& post) {
  if (o.deflection < RP_DEFLECTION_OFF || o.deflection > RP_DEFLECTION_COMPENSATE) {
    throw AbiError{RP_ERR_BAD_INPUT,
                   fmt::format("options.deflection is {}: use RP_DEFLECTION_OFF, "
                               "RP_DEFLECTION_PREDICT or RP_DEFLECTION_COMPENSATE",
                               o.deflection)};
  }
  post.deflection = o.deflection == RP_DEFLECTION_COMPENSATE ? DeflectionMode::compensate
                    : o.deflection == RP_DEFLECTION_PREDICT  ? DeflectionMode::predict
                                                             : DeflectionMode::off;
  if (o.cutting_path) {
    if (post.deflection == DeflectionMode::off) {
      throw AbiError{RP_ERR_BAD_INPUT, "cutting conditions were given (" +
                                           std::string(o.cutting_path) +
                                           ") but no deflection prediction was asked: set "
                                           "options.deflection"};
    }
    post.cutting = load_cutting_table(o.cutting_path);
  }
  post.deflection_tolerance_mm = o.deflection_tolerance_mm;
}

}  // namespace redpost::abi

using namespace redpost::abi;

extern "C" {

RP_API const char* rp_version(void) {
  return REDPOST_VERSION;
}

RP_API void rp_options_init(rp_options* options) {
  if (!options)
    return;
  std::memset(options, 0, sizeof *options);
  options->struct_size = sizeof *options;
  options->apo_mm = 0.5;
  options->cl_line_every = 50;
  options->chordal_tolerance_mm = 0.01;
  options->rapid_velocity_m_per_s = 0.25;
  options->plan = RP_PLAN_GLOBAL;
  options->plan_preset = RP_PLAN_SMOOTH;
  options->keyframe_spacing_mm = 20.0;
  options->deflection_tolerance_mm = 0.05;
  options->fit_tolerance_mm = 0.01;
  options->fit_angle_tolerance_deg = 0.1;
  options->plan_threads = 1;
  options->collision_margin_mm = 5.0;
  options->collision_check = 1;
  for (double& v : options->lock_value)
    v = std::numeric_limits<double>::quiet_NaN();
}

RP_API rp_status rp_open(const rp_options* options, rp_session** session) {
  if (!session)
    return null_handle("the session pointer");
  *session = nullptr;
  if (!options)
    return null_handle("options");
  std::unique_ptr<rp_session> s;
  const rp_status st = guard(t_error, "", [&] {
    // A host built against an older, shorter rp_options gets the defaults for the newer fields.
    if (options->struct_size == 0 || options->struct_size > sizeof(rp_options)) {
      throw AbiError{RP_ERR_BAD_INPUT, "options.struct_size is " +
                                           std::to_string(options->struct_size) +
                                           ": initialise the options with rp_options_init"};
    }
    rp_options o;
    rp_options_init(&o);
    std::memcpy(&o, options, options->struct_size);
    // A host built against 0.7 knows nothing of the point reduction: it gets the program of 0.7,
    // one motion per CL point, not the 0.8 default.
    if (options->struct_size < offsetof(rp_options, fit_tolerance_mm) + sizeof o.fit_tolerance_mm)
      o.fit_tolerance_mm = 0.0;

    const std::string cell_path = required(o.cell_path, "options.cell_path");
    const std::string output_dir = required(o.output_dir, "options.output_dir");
    const std::string name = required(o.program_name, "options.program_name");
    if (const std::string why = redpost::chordal_tolerance_problem(o.chordal_tolerance_mm);
        !why.empty()) {
      throw AbiError{RP_ERR_BAD_INPUT, why};
    }
    redpost::PointReductionOptions reduction;
    reduction.tolerance_mm = o.fit_tolerance_mm;
    reduction.axis_tolerance_deg = o.fit_angle_tolerance_deg;
    if (const std::string why = redpost::point_reduction_problem(reduction); !why.empty())
      throw AbiError{RP_ERR_BAD_INPUT, why};

    // An output that names an input (or another output) would destroy it: refused before
    // anything is read or written.
    const std::string source = o.source_name ? o.source_name : "<events>";
    const auto program_file = [&](const char* ext) {
      return (std::filesystem::path(output_dir) / (name + ext)).string();
    };
    redpost::check_distinct_files({{"the cell file", cell_path},
                                   {"the template set", o.krl_path ? o.krl_path : ""},
                                   {"the tool table", o.tools_path ? o.tools_path : ""},
                                   {"the cutting conditions", o.cutting_path ? o.cutting_path : ""},
                                   {"the CL input", source}},
                                  {{"the program's .src", program_file(".src")},
                                   {"the program's .dat", program_file(".dat")},
                                   {"the joints CSV", o.joints_csv_path ? o.joints_csv_path : ""},
                                   {"the report", o.report_path ? o.report_path : ""}});

    s = std::make_unique<rp_session>();
    s->cell = redpost::load_cell(cell_path);
    s->templates = redpost::load_krl_templates(template_set_path(o.krl_path));

    redpost::PostOptions post;
    post.program.name = name;
    post.program.output_dir = output_dir;
    post.program.base =
        o.base ? std::string(o.base) : fmt::format("BASE_DATA[{}]", s->cell.controller.base_data);
    if (o.tool)
      post.program.tool = o.tool;
    post.program.apo_mm = o.apo_mm;
    post.program.motions_per_file = o.motions_per_file;
    post.program.cl_line_every = o.cl_line_every;
    post.program.header_comment =
        fmt::format("redpost {}, cell {}, from {}", REDPOST_VERSION, s->cell.name,
                    std::filesystem::path(source).filename().string());
    post.source_name = source;
    if (o.joints_csv_path)
      post.joints_csv_path = o.joints_csv_path;
    post.chordal_tolerance_mm = o.chordal_tolerance_mm;
    post.reduction = reduction;
    post.program.max_file_bytes = o.max_file_bytes;
    post.rapid_velocity_m_per_s = o.rapid_velocity_m_per_s;
    if (o.has_clearance) {
      if (!std::isfinite(o.clearance_z_mm))
        throw AbiError{RP_ERR_BAD_INPUT, "the clearance height is not a finite number"};
      post.clearance_z_mm = o.clearance_z_mm;
    }
    if (o.tools_path)
      post.tools = redpost::load_tool_table(o.tools_path);
    set_placement(o, post);
    s->T_B_part = post.T_B_part;
    if (o.msys != RP_MSYS_IGNORE && o.msys != RP_MSYS_APPLY) {
      throw AbiError{
          RP_ERR_BAD_INPUT,
          fmt::format("options.msys is {}: use RP_MSYS_IGNORE or RP_MSYS_APPLY", o.msys)};
    }
    post.msys = o.msys == RP_MSYS_APPLY ? redpost::MsysMode::apply : redpost::MsysMode::ignore;
    set_plan_options(o, s->cell, post);
    set_deflection_options(o, post);
    set_collision_options(o, post);
    s->conditioning_threshold = post.tracker.gains.conditioning_threshold;
    s->post = std::make_unique<redpost::PostSession>(s->cell, s->templates, post);
    s->source = source;
    s->cell_path = cell_path;
    s->program = name;
    open_report(s.get(), o);
    if (o.pipeline)
      s->start_pipeline();
  });
  if (st == RP_OK)
    *session = s.release();
  return st;
}

namespace {

// The end of a session, in one or two steps (rp_prepare, then rp_close). A failure of either
// fails the session and removes every temporary: nothing is written.
rp_status end_session(rp_session* session, bool commit) {
  if (!session)
    return null_handle("the session");
  using State = rp_session::State;
  // Every event tracked first; one that failed on the pipeline's thread is told here, with its
  // message, and nothing is written.
  session->sync();
  if (session->state == State::open || session->state == State::prepared) {
    if (const rp_status failed = session->take_pipeline_failure(); failed != RP_OK) {
      session->abandon();
      return failed;
    }
  }
  const State before = session->state;
  const char* call = commit ? "close" : "prepare";
  const rp_status s = guard(session->error, "", [&] {
    if (session->state == State::closed)
      throw AbiError{RP_ERR_STATE, std::string(call) + " refused: the session is already closed"};
    if (session->state == State::failed) {
      session->abandon();  // removes the temporary files: a failed session writes nothing
      throw AbiError{RP_ERR_STATE, std::string(call) +
                                       " refused: nothing written, the session failed at " +
                                       session->failure};
    }
    if (!commit && session->state == State::prepared)
      throw AbiError{RP_ERR_STATE, "prepare refused: the session is already prepared"};
    if (session->state != State::prepared) {
      session->run_noting_line([&] { session->post->prepare(); });
      prepare_report(session);
    }
    if (commit) {
      session->post->finish();
      commit_report(session);
      session->state = State::closed;
    } else {
      session->state = State::prepared;
    }
  });
  if (s != RP_OK && (before == State::open || before == State::prepared) &&
      session->state != State::closed && session->state != State::failed) {
    // prepare() or finish() failed (no move, a file that cannot be completed): nothing is
    // left behind, and an old program of the same name is kept.
    session->state = State::failed;
    try {
      session->failure = std::string(call) + ": " + session->error;
      session->abandon();
    } catch (...) {
      session->post.reset();
    }
  }
  return s;
}

}  // namespace

RP_API rp_status rp_prepare(rp_session* session) {
  return end_session(session, false);
}

RP_API rp_status rp_close(rp_session* session) {
  return end_session(session, true);
}

RP_API void rp_remove_temporaries(void) {
  redpost::stop_and_remove_temporaries();
}

RP_API void rp_free(rp_session* session) {
  delete session;
}

RP_API const char* rp_last_error(const rp_session* session) {
  return session ? session->error.c_str() : t_error.c_str();
}

RP_API int rp_last_error_line(const rp_session* session) {
  return session ? session->error_line : 0;
}

RP_API rp_status rp_last_move(const rp_session* session, rp_move_info* info) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!info)
      throw AbiError{RP_ERR_NULL, "rp_last_move: info is NULL"};
    const redpost::PoseResult& r = session->pose();
    if (r.q.size() == 0)
      throw AbiError{RP_ERR_STATE, "rp_last_move: no pose has been tracked yet"};
    rp_move_info out{};
    out.joint_count = static_cast<int>(r.q.size());
    for (int i = 0; i < out.joint_count && i < 16; ++i)
      out.joints[i] = r.q[i];
    const redpost::AxisValues axes = redpost::to_controller_axes(session->cell, r.q);
    for (int i = 0; i < 12; ++i)
      out.axes[i] = axes.value[static_cast<std::size_t>(i)];
    out.inv_condition = r.inv_condition;
    out.iterations = r.iterations;
    out.position_error_mm = r.position_error_mm;
    out.orientation_error_rad = r.orientation_error_rad;
    out.limit_margin = r.limit_margin;
    *info = out;
  });
}

RP_API rp_status rp_sync(rp_session* session) {
  if (!session)
    return null_handle("the session");
  session->sync();
  if (session->state == rp_session::State::open) {
    if (const rp_status failed = session->take_pipeline_failure(); failed != RP_OK)
      return failed;
  }
  return RP_OK;
}

RP_API rp_status rp_summary_get(const rp_session* session, rp_summary* summary) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!summary)
      throw AbiError{RP_ERR_NULL, "rp_summary_get: summary is NULL"};
    const redpost::PostSummary& s = session->summary();
    summary->poses = s.poses;
    summary->motions = s.motions;
    summary->lowest_inv_condition = s.lowest_inv_condition;
    summary->lowest_inv_condition_line = s.lowest_inv_condition_line;
    summary->warnings = static_cast<int>(s.warnings.size() + session->host_warnings.size());
  });
}

RP_API rp_status rp_joint_range(const rp_session* session, int index, rp_joint_range_info* range) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!range)
      throw AbiError{RP_ERR_NULL, "rp_joint_range: range is NULL"};
    const redpost::PostSummary& s = session->summary();
    if (index < 0 || index >= session->cell.size() ||
        static_cast<std::size_t>(index) >= s.joints.size()) {
      throw AbiError{RP_ERR_BAD_INPUT, "rp_joint_range: the cell has no joint " +
                                           std::to_string(index) + " (it has " +
                                           std::to_string(session->cell.size()) + ")"};
    }
    const redpost::Joint& j = session->cell.joint(index);
    const redpost::JointRange& r = s.joints[static_cast<std::size_t>(index)];
    const bool prismatic = j.type == redpost::JointType::prismatic;
    // Values as the robot programmer reads them (controller units where the joint has an axis);
    // distances in deg or mm.
    auto value = [&](double q) {
      return j.axis.mapped() ? redpost::to_axis_value(j, q)
             : prismatic     ? q
                             : redpost::rad_to_deg(q);
    };
    auto distance = [&](double d) { return prismatic ? d : redpost::rad_to_deg(d); };
    rp_joint_range_info out{};
    out.name = j.name.c_str();
    out.prismatic = prismatic ? 1 : 0;
    out.lowest = value(r.lowest);
    out.highest = value(r.highest);
    out.margin_lower = distance(r.margin_lower);
    out.margin_upper = distance(r.margin_upper);
    // A negative sign swaps the ends of the range in controller units.
    if (j.axis.mapped() && j.axis.sign < 0) {
      std::swap(out.lowest, out.highest);
      std::swap(out.margin_lower, out.margin_upper);
    }
    out.axis_name = static_axis_name(j.axis);
    *range = out;
  });
}

RP_API rp_status rp_timing_get(const rp_session* session, rp_timing* timing) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!timing)
      throw AbiError{RP_ERR_NULL, "rp_timing_get: timing is NULL"};
    check_struct_size(timing, "rp_timing_get", "rp_timing");
    const redpost::PostSummary& s = session->summary();
    rp_timing out{};
    out.cycle_time_s = s.cycle_time_s;
    out.cutting_time_s = s.cutting_time_s;
    out.feed_time_s = s.feed_time_s;
    out.axis_speeds_known = s.axis_speeds_known ? 1 : 0;
    out.slowed_motions = s.slowed_motions;
    out.peak_speed_fraction = s.peak_speed_fraction;
    out.peak_speed_joint = s.peak_speed_joint;
    out.peak_speed_line = s.peak_speed_line;
    out.feed_limits = s.feed_limits_total;
    out.feed_limits_listed = static_cast<int>(s.feed_limits.size());
    out.untimed_tool_changes = s.untimed_tool_changes;
    out.plan_windows = s.plan_windows;
    out.plan_fallback_windows = s.plan_fallback_windows;
    out.plan_still_windows = s.plan_still_windows;
    out.plan_ik_evaluations = s.plan_ik_evaluations;
    out.interpolation_cycle_s = s.interpolation_cycle_s;
    out.cp_motions = s.cp_motions;
    out.below_cycle_motions = s.below_cycle_motions;
    out.rate_limited_motions = s.rate_limited_motions;
    out.lookahead_limited_motions = s.lookahead_limited_motions;
    out.shortest_motion_s = s.shortest_motion_s;
    out.shortest_motion_line = s.shortest_motion_line;
    out.reducible_points = s.reducible_points;
    out.reduced_moves = s.reduced_moves;
    out.rate_slowed_motions = s.rate_slowed_motions;
    out.reduced_arcs = s.reduced_arcs;
    copy_sized(timing, out);
  });
}

RP_API rp_status rp_feed_limit(const rp_session* session, int index, rp_feed_limit_info* info) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!info)
      throw AbiError{RP_ERR_NULL, "rp_feed_limit: info is NULL"};
    check_struct_size(info, "rp_feed_limit", "rp_feed_limit_info");
    const std::vector<redpost::FeedLimit>& all = session->summary().feed_limits;
    if (index < 0 || static_cast<std::size_t>(index) >= all.size()) {
      throw AbiError{RP_ERR_BAD_INPUT, "rp_feed_limit: no stretch " + std::to_string(index) + " (" +
                                           std::to_string(all.size()) + " listed)"};
    }
    const redpost::FeedLimit& f = all[static_cast<std::size_t>(index)];
    rp_feed_limit_info out{};
    out.first_line = f.first_line;
    out.last_line = f.last_line;
    out.motions = f.motions;
    out.joint = f.joint;
    out.joint_name = "";
    out.axis_name = "-";
    if (f.joint >= 0) {
      const redpost::Joint& j = session->cell.joint(f.joint);
      out.joint_name = j.name.c_str();
      out.axis_name = static_axis_name(j.axis);
    }
    out.limit = redpost::to_string(f.limit);
    out.lowest_mm_per_min = f.lowest_mm_per_min;
    out.asked_mm_per_min = f.asked_mm_per_min;
    copy_sized(info, out);
  });
}

RP_API rp_status rp_deflection_summary_get(const rp_session* session,
                                           rp_deflection_summary* summary) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!summary)
      throw AbiError{RP_ERR_NULL, "rp_deflection_summary_get: summary is NULL"};
    check_struct_size(summary, "rp_deflection_summary_get", "rp_deflection_summary");
    const redpost::PostSummary& s = session->summary();
    rp_deflection_summary out{};
    out.mode = s.deflection_mode == redpost::DeflectionMode::compensate ? RP_DEFLECTION_COMPENSATE
               : s.deflection_mode == redpost::DeflectionMode::predict  ? RP_DEFLECTION_PREDICT
                                                                        : RP_DEFLECTION_OFF;
    out.tolerance_mm = s.deflection_tolerance_mm;
    out.operations = static_cast<int>(s.deflection.size());
    out.unloaded_moves = s.unloaded_moves;
    out.compensation_iterations = s.compensation_iterations;
    out.max_compensation_iterations = s.max_compensation_iterations;
    copy_sized(summary, out);
  });
}

RP_API rp_status rp_collision_get(const rp_session* session, rp_collision_summary* summary) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!summary)
      throw AbiError{RP_ERR_NULL, "rp_collision_get: summary is NULL"};
    check_struct_size(summary, "rp_collision_get", "rp_collision_summary");
    const redpost::PostSummary& s = session->summary();
    rp_collision_summary out{};
    out.checked = s.collision_checked ? 1 : 0;
    out.bodies = s.collision_bodies;
    out.pairs = s.collision_pairs;
    out.margin_mm = s.collision_margin_mm;
    out.least_clearance_mm = s.least_clearance_mm;
    out.least_clearance_line = s.least_clearance_line;
    out.least_clearance_pair = s.least_clearance_pair.c_str();
    out.distance_queries = s.clearance_queries;
    out.proven_clearance_mm = s.proven_clearance_mm;
    copy_sized(summary, out);
  });
}

RP_API rp_status rp_deflection_get(const rp_session* session, int index, rp_deflection_info* info) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!info)
      throw AbiError{RP_ERR_NULL, "rp_deflection_get: info is NULL"};
    check_struct_size(info, "rp_deflection_get", "rp_deflection_info");
    const std::vector<redpost::DeflectionStats>& all = session->summary().deflection;
    if (index < 0 || static_cast<std::size_t>(index) >= all.size()) {
      throw AbiError{RP_ERR_BAD_INPUT, "rp_deflection_get: no operation " + std::to_string(index) +
                                           " (" + std::to_string(all.size()) + " with a load)"};
    }
    const redpost::DeflectionStats& d = all[static_cast<std::size_t>(index)];
    rp_deflection_info out{};
    out.operation = d.operation.c_str();
    out.first_line = d.first_line;
    out.last_line = d.last_line;
    out.motions = d.motions;
    out.max_mm = d.max_mm;
    out.rms_mm = d.rms_mm;
    out.max_normal_mm = d.max_normal_mm;
    out.rms_normal_mm = d.rms_normal_mm;
    out.max_normal_line = d.max_normal_line;
    out.max_rotation_rad = d.max_rotation_rad;
    out.max_force_N = d.max_force_N;
    out.over_tolerance = d.over_tolerance;
    out.max_residual_mm = d.max_residual_mm;
    out.max_residual_normal_mm = d.max_residual_normal_mm;
    out.over_tolerance_after = d.over_tolerance_after;
    out.max_compensation_mm = d.max_compensation_mm;
    copy_sized(info, out);
  });
}

RP_API const char* rp_warning(const rp_session* session, int index) {
  if (!session || index < 0)
    return nullptr;
  return session->warning(static_cast<std::size_t>(index));
}

RP_API const char* rp_output_file(const rp_session* session, int index) {
  if (!session || index < 0 || session->state != rp_session::State::closed)
    return nullptr;
  const std::vector<std::string>& f = session->summary().files;
  return static_cast<std::size_t>(index) < f.size() ? f[static_cast<std::size_t>(index)].c_str()
                                                    : nullptr;
}

// --- Reader -------------------------------------------------------------------------------

}  // extern "C"
