// The C ABI's event calls (redpost.h): every call becomes one ClEvent of the event model
// (redpost/cl/event.hpp) and goes through the session's front door (PostSession::handle), as
// the CL reader's events do (rp_session_event), so that every host gets the same program from
// the same toolpath.
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "abi_internal.hpp"
#include "redpost.h"

using namespace redpost::abi;

namespace {

using redpost::ClEvent;
using redpost::ClEventKind;

// The event of a call, at the session's current line.
ClEvent event_of(const rp_session* session, ClEventKind kind) {
  ClEvent e;
  e.kind = kind;
  e.line = session->current_line();
  return e;
}

// One call: counted, refused unless open, failing the session if the event is refused.
template <class F>
rp_status send_with(rp_session* session, ClEventKind kind, F&& fill) {
  if (!session)
    return null_handle("the session");
  return session->event([&] {
    ClEvent e = event_of(session, kind);
    fill(e);
    session->submit(std::move(e));
  });
}

rp_status send_plain(rp_session* session, ClEventKind kind) {
  return send_with(session, kind, [](ClEvent&) {});
}

redpost::SpindleDirection direction_of(const rp_spindle_direction& direction) {
  switch (enum_value(direction)) {
    case RP_SPINDLE_OFF:
      return redpost::SpindleDirection::off;
    case RP_SPINDLE_CW:
      return redpost::SpindleDirection::clockwise;
    case RP_SPINDLE_CCW:
      return redpost::SpindleDirection::counter_clockwise;
    default:
      break;
  }
  throw AbiError{RP_ERR_BAD_INPUT, "spindle direction " + std::to_string(enum_value(direction)) +
                                       " is not one of RP_SPINDLE_OFF, _CW, _CCW"};
}

}  // namespace

extern "C" {

RP_API rp_status rp_set_line(rp_session* session, int line) {
  if (!session)
    return null_handle("the session");
  // Not an event: a line that cannot be one is refused and the session goes on with the line it
  // had (a query-like call, as rp_last_move is).
  if (line < 0) {
    return guard(session->error, "", [&] {
      throw AbiError{RP_ERR_BAD_INPUT, "rp_set_line: line " + std::to_string(line) +
                                           " is negative (0 numbers the events again)"};
    });
  }
  session->line = line;
  session->line_set = line > 0;
  return RP_OK;
}

RP_API rp_status rp_tool_change(rp_session* session, int number, const char* name,
                                double diameter_mm, double length_mm) {
  return send_with(session, ClEventKind::tool_change, [&](ClEvent& e) {
    e.tool_number = number;
    e.text = name ? name : "";
    e.tool_diameter_mm = diameter_mm;
    e.tool_length_mm = length_mm;
  });
}

RP_API rp_status rp_spindle(rp_session* session, double rpm, rp_spindle_direction direction) {
  return send_with(session, ClEventKind::spindle, [&](ClEvent& e) {
    e.value = rpm;
    e.direction = direction_of(direction);
  });
}

RP_API rp_status rp_feed(rp_session* session, double mm_per_min) {
  return send_with(session, ClEventKind::feed, [&](ClEvent& e) { e.value = mm_per_min; });
}

RP_API rp_status rp_rapid(rp_session* session) {
  return send_plain(session, ClEventKind::rapid);
}

RP_API rp_status rp_linear_move(rp_session* session, double x, double y, double z, double i,
                                double j, double k) {
  return send_with(session, ClEventKind::move, [&](ClEvent& e) {
    e.p_mm = vec(x, y, z);
    e.tool_axis = vec(i, j, k);
  });
}

RP_API rp_status rp_circular_move(rp_session* session, double cx, double cy, double cz, double ax,
                                  double ay, double az, double radius_mm, double x, double y,
                                  double z, double i, double j, double k) {
  return send_with(session, ClEventKind::arc, [&](ClEvent& e) {
    e.arc_centre_mm = vec(cx, cy, cz);
    e.arc_axis = vec(ax, ay, az);
    e.value = radius_mm;
    e.p_mm = vec(x, y, z);
    e.tool_axis = vec(i, j, k);
    e.origin = redpost::MoveOrigin::arc;
  });
}

RP_API rp_status rp_operation_start(rp_session* session, const char* name) {
  return send_with(session, ClEventKind::operation_start,
                   [&](ClEvent& e) { e.text = required(name, "the operation name"); });
}

RP_API rp_status rp_operation_end(rp_session* session) {
  return send_plain(session, ClEventKind::operation_end);
}

RP_API rp_status rp_coolant(rp_session* session, int on, const char* mode) {
  return send_with(session, ClEventKind::coolant, [&](ClEvent& e) {
    e.flag = on != 0;
    e.text = mode ? mode : "";
  });
}

RP_API rp_status rp_comment(rp_session* session, const char* text) {
  return send_with(session, ClEventKind::comment,
                   [&](ClEvent& e) { e.text = required(text, "the comment"); });
}

RP_API rp_status rp_literal(rp_session* session, const char* text) {
  return send_with(session, ClEventKind::literal,
                   [&](ClEvent& e) { e.text = required(text, "the literal"); });
}

// --- Added in 0.6 ----------------------------------------------------------------------------

RP_API void rp_cycle_params_init(rp_cycle_params* params) {
  if (!params)
    return;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  *params = rp_cycle_params{};
  params->struct_size = sizeof *params;
  params->depth_mm = params->clearance_mm = params->retract_mm = nan;
  params->feed_mm_per_min = params->first_peck_mm = params->next_peck_mm = nan;
}

RP_API rp_status rp_cycle_define(rp_session* session, const rp_cycle_params* params) {
  return send_with(session, ClEventKind::cycle, [&](ClEvent& e) {
    if (!params)
      throw AbiError{RP_ERR_NULL, "the cycle's parameters are NULL"};
    cycle_from(*params, e);
  });
}

RP_API rp_status rp_cycle_hole(rp_session* session, double x, double y, double z, double i,
                               double j, double k) {
  return send_with(session, ClEventKind::hole, [&](ClEvent& e) {
    e.p_mm = vec(x, y, z);
    e.tool_axis = vec(i, j, k);
  });
}

RP_API rp_status rp_cycle_on(rp_session* session) {
  return send_plain(session, ClEventKind::cycle_on);
}

RP_API rp_status rp_cycle_off(rp_session* session) {
  return send_plain(session, ClEventKind::cycle_off);
}

RP_API rp_status rp_nurbs_move(rp_session* session, const double* knots, int knot_count,
                               const double* points, int point_count, double i, double j,
                               double k) {
  return send_with(session, ClEventKind::nurbs, [&](ClEvent& e) {
    nurbs_from(knots, knot_count, points, point_count, e);
    e.tool_axis = vec(i, j, k);
    e.origin = redpost::MoveOrigin::nurbs;
  });
}

RP_API rp_status rp_machine_frame(rp_session* session, const double* origin, const double* x_axis,
                                  const double* y_axis) {
  return send_with(session, ClEventKind::msys, [&](ClEvent& e) {
    if (!origin || !x_axis || !y_axis)
      throw AbiError{RP_ERR_NULL, "rp_machine_frame: an array is NULL"};
    e.p_mm = vec(origin[0], origin[1], origin[2]);
    e.msys_x = vec(x_axis[0], x_axis[1], x_axis[2]);
    e.msys_y = vec(y_axis[0], y_axis[1], y_axis[2]);
  });
}

RP_API rp_status rp_dwell(rp_session* session, double seconds) {
  return send_with(session, ClEventKind::dwell, [&](ClEvent& e) { e.value = seconds; });
}

RP_API rp_status rp_cutcom(rp_session* session, int on, const char* side) {
  return send_with(session, ClEventKind::cutcom, [&](ClEvent& e) {
    e.flag = on != 0;
    e.text = side ? side : (on ? "ON" : "OFF");
  });
}

RP_API rp_status rp_operator_text(rp_session* session, rp_text_kind kind, const char* text) {
  return send_with(session, ClEventKind::operator_text, [&](ClEvent& e) {
    e.text = required(text, "the text");
    e.text_kind = text_kind_of(kind);  // by reference: the value is read as an int
  });
}

RP_API rp_status rp_warn(rp_session* session, const char* text) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (session->state != rp_session::State::open)
      throw AbiError{RP_ERR_STATE, "rp_warn: the session is not open (prepared, closed or failed)"};
    const std::string w = required(text, "the warning");
    session->host_warnings.push_back(w.substr(0, 4096));
  });
}

}  // extern "C"
