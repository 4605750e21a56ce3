// The C ABI's motion observer and the session's report (redpost.h: rp_set_motion_observer,
// rp_options.report_path): every written motion as an rp_motion, to the host's observer and to
// the report (plugin/src/report), which the library writes with the program, so that every host
// (redpost convert, the NX handlers) gets the same report from the same toolpath.
#include <chrono>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "abi_internal.hpp"
#include "redpost.h"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/output_target.hpp"
#include "report/convert_report.hpp"

namespace redpost::abi {

namespace {

// One motion as the ABI gives it; filled on the stack: no allocation on the per-pose path.
void fill_motion(const redpost::MotionSample& m, double threshold, rp_motion& out) {
  std::memset(&out, 0, sizeof out);
  out.struct_size = sizeof out;
  out.index = m.index;
  switch (m.kind) {
    case redpost::KrlMotionKind::ptp_axes:
      out.kind = RP_MOTION_PTP;
      break;
    case redpost::KrlMotionKind::rapid:
      out.kind = RP_MOTION_RAPID;
      break;
    case redpost::KrlMotionKind::lin:
      out.kind = RP_MOTION_LIN;
      break;
  }
  out.line = m.cl_line;
  out.joint_count = static_cast<int>(m.q->size());
  for (int i = 0; i < out.joint_count && i < 16; ++i)
    out.joints[i] = (*m.q)[i];
  for (int i = 0; i < 12; ++i)
    out.axes[i] = m.axes->value[static_cast<std::size_t>(i)];
  out.inv_condition = m.inv_condition;
  out.conditioning_threshold = threshold;
  out.iterations = m.iterations;
  out.feed_mm_per_min = m.feed_mm_per_min;
  for (int i = 0; i < 3; ++i)
    out.tcp[i] = m.p_part_mm[i];
  out.time_s = m.time_s;
  out.duration_s = m.duration_s;
  out.speed_mm_s = m.speed_mm_s;
  out.asked_mm_s = m.asked_mm_s;
  out.command_mm_s = m.command_mm_s;
  out.limit = redpost::to_string(m.limit);
  out.limit_joint = m.limit_joint;
  for (int i = 0; i < out.joint_count && i < 16; ++i)
    out.speed_fraction[i] = m.speed_fraction ? (*m.speed_fraction)[i] : 0.0;
  out.planned = m.q_plan ? 1 : 0;
  for (int i = 0; m.q_plan && i < out.joint_count && i < 16; ++i)
    out.planned_joints[i] = (*m.q_plan)[i];
  if (const redpost::MotionDeflection* d = m.deflection) {
    out.has_deflection = 1;
    for (int i = 0; i < 3; ++i) {
      out.deflection_mm[i] = d->translation_mm[i];
      out.deflection_rotation_rad[i] = d->rotation_rad[i];
    }
    out.deflection_normal_mm = d->normal_mm;
    out.cutting_force_N = d->force_N;
    out.compensation_mm = d->compensation_mm;
    out.residual_mm = d->residual_mm;
    out.residual_normal_mm = d->residual_normal_mm;
    out.compensation_iterations = d->iterations;
  }
  out.tool_length_mm = m.tool_length_mm;
  out.tcp_shift_mm = m.tcp_shift_mm;
  out.clearance_mm = m.clearance_mm;
  out.clearance_proven_mm = m.clearance_proven_mm;
  out.clearance_pair = m.clearance_pair ? m.clearance_pair->c_str() : "";
  out.clearance_exact = m.clearance_exact ? 1 : 0;
  for (int i = 0; i < 3; ++i) {
    out.clearance_point_a[i] = m.clearance_point_a[i];
    out.clearance_point_b[i] = m.clearance_point_b[i];
  }
}

}  // namespace

// The session's observer: set while the host has one or a report is made.
void install_observer(rp_session* session) {
  session->sync();  // the pipeline's thread is not inside the observer while it changes
  if (!session->host_observer && !session->report) {
    session->post->set_motion_observer({});
    return;
  }
  session->post->set_motion_observer([session](const redpost::MotionSample& m) {
    rp_motion out;
    fill_motion(m, session->conditioning_threshold, out);
    if (session->report)
      session->report->on_motion(out);
    if (session->host_observer)
      session->host_observer(&out, session->host_user);
  });
}

void open_report(rp_session* session, const rp_options& o) {
  if (!o.report_path)
    return;
  session->report_path = o.report_path;
  redpost::check_output_target(session->report_path, "the report");
  redpost::check_output_folder(session->report_path, "the report");
  session->report = std::make_unique<redpost::run_report::ConvertReport>(session);
  install_observer(session);
}

// After the program is prepared: the report written to its temporary and flushed, so that a
// report that cannot be written stops the run before the program replaces an old one.
void prepare_report(rp_session* session) {
  if (!session->report)
    return;
  redpost::run_report::ConvertReportContext context;
  context.input = session->source;
  context.cell = session->cell_path;
  context.program = session->program;
  context.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - session->opened).count();
  session->report_file.emplace(std::vector<redpost::TextOutput>{redpost::TextOutput{
      session->report_path, session->report->html(session->report_path, session, context)}});
}

void commit_report(rp_session* session) {
  if (session->report_file)
    session->report_file->commit();
  session->report_file.reset();
}

}  // namespace redpost::abi

using namespace redpost::abi;

extern "C" {

RP_API rp_status rp_set_motion_observer(rp_session* session, rp_motion_observer fn, void* user) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (session->state != rp_session::State::open || !session->post) {
      throw AbiError{RP_ERR_STATE,
                     "rp_set_motion_observer: the session is not open (closed or failed)"};
    }
    session->host_observer = fn;
    session->host_user = fn ? user : nullptr;
    install_observer(session);
  });
}

}  // extern "C"
