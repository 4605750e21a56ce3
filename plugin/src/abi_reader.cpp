// The C ABI's CL reader (redpost.h): rp_reader_* over redpost::ClReader, and reader events sent
// to a session (rp_session_event), as `redpost convert` and the C host do for every event.
#include <cmath>
#include <cstddef>
#include <cstring>
#include <deque>
#include <string>

#include <fmt/format.h>

#include "abi_internal.hpp"
#include "redpost/io/text_file.hpp"

using namespace redpost::abi;

namespace {

using redpost::ClEventKind;
using redpost::MoveOrigin;

// The ABI's kind of a reader event (a FROM and a GODLTA are moves of their own kinds).
rp_event_kind abi_kind_of(const redpost::ClEvent& e) {
  switch (e.kind) {
    case ClEventKind::part_name:
      return RP_EVENT_PART_NAME;
    case ClEventKind::tool_change:
      return RP_EVENT_TOOL_CHANGE;
    case ClEventKind::spindle:
      return RP_EVENT_SPINDLE;
    case ClEventKind::feed:
      return RP_EVENT_FEED;
    case ClEventKind::rapid:
      return RP_EVENT_RAPID;
    case ClEventKind::move:
      return e.origin == MoveOrigin::from_point ? RP_EVENT_FROM
             : e.origin == MoveOrigin::delta    ? RP_EVENT_GODLTA
                                                : RP_EVENT_MOVE;
    case ClEventKind::coolant:
      return RP_EVENT_COOLANT;
    case ClEventKind::operation_start:
      return RP_EVENT_OPERATION_START;
    case ClEventKind::operation_end:
      return RP_EVENT_OPERATION_END;
    case ClEventKind::comment:
      return RP_EVENT_COMMENT;
    case ClEventKind::literal:
      return RP_EVENT_LITERAL;
    case ClEventKind::unknown_word:
      return RP_EVENT_UNKNOWN_WORD;
    case ClEventKind::end_of_program:
      return RP_EVENT_END_OF_PROGRAM;
    case ClEventKind::dwell:
      return RP_EVENT_DWELL;
    case ClEventKind::machine_frame:
      return RP_EVENT_MACHINE_FRAME;
    case ClEventKind::arc:
      return RP_EVENT_ARC;
    case ClEventKind::cycle:
      return RP_EVENT_CYCLE;
    case ClEventKind::cycle_on:
      return RP_EVENT_CYCLE_ON;
    case ClEventKind::cycle_off:
      return RP_EVENT_CYCLE_OFF;
    case ClEventKind::hole:
      return RP_EVENT_HOLE;
    case ClEventKind::nurbs:
      return RP_EVENT_NURBS;
    case ClEventKind::msys:
      return RP_EVENT_MSYS;
    case ClEventKind::operator_text:
      return RP_EVENT_OPERATOR_TEXT;
    case ClEventKind::cutcom:
      return RP_EVENT_CUTCOM;
  }
  return RP_EVENT_UNKNOWN_WORD;
}

// The session's kind (and a move's origin) of an ABI event.
void set_kind_of(const rp_event& event, redpost::ClEvent& e) {
  static constexpr struct {
    rp_event_kind abi;
    ClEventKind kind;
  } kKinds[] = {
      {RP_EVENT_PART_NAME, ClEventKind::part_name},
      {RP_EVENT_TOOL_CHANGE, ClEventKind::tool_change},
      {RP_EVENT_SPINDLE, ClEventKind::spindle},
      {RP_EVENT_FEED, ClEventKind::feed},
      {RP_EVENT_RAPID, ClEventKind::rapid},
      {RP_EVENT_MOVE, ClEventKind::move},
      {RP_EVENT_COOLANT, ClEventKind::coolant},
      {RP_EVENT_OPERATION_START, ClEventKind::operation_start},
      {RP_EVENT_OPERATION_END, ClEventKind::operation_end},
      {RP_EVENT_COMMENT, ClEventKind::comment},
      {RP_EVENT_LITERAL, ClEventKind::literal},
      {RP_EVENT_UNKNOWN_WORD, ClEventKind::unknown_word},
      {RP_EVENT_END_OF_PROGRAM, ClEventKind::end_of_program},
      {RP_EVENT_DWELL, ClEventKind::dwell},
      {RP_EVENT_MACHINE_FRAME, ClEventKind::machine_frame},
      {RP_EVENT_ARC, ClEventKind::arc},
      {RP_EVENT_CYCLE, ClEventKind::cycle},
      {RP_EVENT_CYCLE_ON, ClEventKind::cycle_on},
      {RP_EVENT_CYCLE_OFF, ClEventKind::cycle_off},
      {RP_EVENT_HOLE, ClEventKind::hole},
      {RP_EVENT_NURBS, ClEventKind::nurbs},
      {RP_EVENT_MSYS, ClEventKind::msys},
      {RP_EVENT_OPERATOR_TEXT, ClEventKind::operator_text},
      {RP_EVENT_CUTCOM, ClEventKind::cutcom},
      {RP_EVENT_FROM, ClEventKind::move},
      {RP_EVENT_GODLTA, ClEventKind::move},
  };
  const int kind = enum_value(event.kind);
  for (const auto& k : kKinds) {
    if (k.abi == kind) {
      e.kind = k.kind;
      e.origin = kind == RP_EVENT_FROM     ? MoveOrigin::from_point
                 : kind == RP_EVENT_GODLTA ? MoveOrigin::delta
                 : kind == RP_EVENT_ARC    ? MoveOrigin::arc
                 : kind == RP_EVENT_NURBS  ? MoveOrigin::nurbs
                                           : MoveOrigin::goto_point;
      return;
    }
  }
  throw AbiError{RP_ERR_BAD_INPUT,
                 "event kind " + std::to_string(kind) + " is not an rp_event_kind"};
}

}  // namespace

extern "C" {

RP_API void rp_reader_options_init(rp_reader_options* options) {
  if (!options)
    return;
  std::memset(options, 0, sizeof *options);
  options->struct_size = sizeof *options;
  options->chordal_tolerance_mm = 0.01;
  options->msys = RP_MSYS_IGNORE;
}

RP_API rp_status rp_reader_open(const char* path, double chordal_tolerance_mm, rp_reader** reader) {
  rp_reader_options o;
  rp_reader_options_init(&o);
  o.chordal_tolerance_mm = chordal_tolerance_mm;
  return rp_reader_open_ex(path, &o, reader);
}

RP_API rp_status rp_reader_open_ex(const char* path, const rp_reader_options* options,
                                   rp_reader** reader) {
  if (!reader)
    return null_handle("the reader pointer");
  *reader = nullptr;
  if (!path)
    return null_handle("the path");
  if (!options)
    return null_handle("the reader options");
  std::unique_ptr<rp_reader> r;
  const rp_status s = guard(t_error, "", [&] {
    if (options->struct_size == 0 || options->struct_size > sizeof(rp_reader_options)) {
      throw AbiError{RP_ERR_BAD_INPUT, "reader options.struct_size is " +
                                           std::to_string(options->struct_size) +
                                           ": initialise them with rp_reader_options_init"};
    }
    rp_reader_options o;
    rp_reader_options_init(&o);
    std::memcpy(&o, options, options->struct_size);
    if (const std::string why = redpost::chordal_tolerance_problem(o.chordal_tolerance_mm);
        !why.empty()) {
      throw AbiError{RP_ERR_BAD_INPUT, why};
    }
    // Read as an int: a host's value outside the enumeration is no rp_msys_mode to load.
    const int msys = enum_value(o.msys);
    if (msys != RP_MSYS_IGNORE && msys != RP_MSYS_APPLY)
      throw AbiError{RP_ERR_BAD_INPUT, "msys is not RP_MSYS_IGNORE or RP_MSYS_APPLY"};
    r = std::make_unique<rp_reader>();
    r->in = redpost::open_text_stream(path);
    redpost::ClReaderOptions read;
    read.chordal_tolerance_mm = o.chordal_tolerance_mm;
    read.msys = msys == RP_MSYS_APPLY ? redpost::MsysMode::apply : redpost::MsysMode::ignore;
    read.arcs_as_events = o.arcs_as_events != 0;
    read.toolpath_events = o.toolpath_events != 0;
    r->toolpath_events = read.toolpath_events;
    r->reader = std::make_unique<redpost::ClReader>(r->in, path, read);
  });
  if (s == RP_OK)
    *reader = r.release();
  return s;
}

RP_API rp_status rp_reader_next(rp_reader* reader, rp_event* event, int* more) {
  if (!reader)
    return null_handle("the reader");
  if (reader->failed != RP_OK) {
    if (more)
      *more = 0;
    return reader->failed;
  }
  const rp_status status = guard(reader->error, "", [&] {
    if (!event || !more)
      throw AbiError{RP_ERR_NULL, "rp_reader_next: event or more is NULL"};
    *more = 0;
    const redpost::ClEvent& e = reader->event;
    if (!reader->reader->next(reader->event))
      return;
    rp_event out{};
    out.kind = abi_kind_of(e);
    if (!reader->toolpath_events && (out.kind == RP_EVENT_FROM || out.kind == RP_EVENT_GODLTA))
      out.kind = RP_EVENT_MOVE;  // the kinds of 0.5 only
    out.line = e.line;
    for (int i = 0; i < 3; ++i) {
      out.p[i] = e.p_mm[i];
      out.axis[i] = e.tool_axis[i];
    }
    out.rapid = e.rapid ? 1 : 0;
    out.tool_number = e.tool_number;
    out.tool_diameter_mm = e.tool_diameter_mm;
    out.tool_length_mm = e.tool_length_mm;
    out.value = e.value;
    switch (e.direction) {
      case redpost::SpindleDirection::off:
        out.direction = RP_SPINDLE_OFF;
        break;
      case redpost::SpindleDirection::clockwise:
        out.direction = RP_SPINDLE_CW;
        break;
      case redpost::SpindleDirection::counter_clockwise:
        out.direction = RP_SPINDLE_CCW;
        break;
    }
    out.flag = e.flag ? 1 : 0;
    out.text = e.text.c_str();  // the reader's event: valid until the next rp_reader_next
    out.has_clearance = e.has_clearance ? 1 : 0;
    for (int i = 0; i < 3; ++i) {
      out.clearance_p[i] = e.clearance_p_mm[i];
      out.arc_centre[i] = e.arc_centre_mm[i];
      out.arc_axis[i] = e.arc_axis[i];
    }
    if (!reader->toolpath_events) {
      // A host built against 0.5 has the fields up to arc_axis only, and this reader gives
      // none of the later kinds: its own part of the struct only.
      std::memcpy(static_cast<void*>(event), &out, offsetof(rp_event, cycle));
      *more = 1;
      return;
    }
    rp_cycle_params_init(&out.cycle);
    out.cycle.peck = e.cycle.deep ? 1 : 0;
    out.cycle.depth_mm = e.cycle.depth_mm;
    out.cycle.clearance_mm = e.cycle.clearance_mm;
    out.cycle.retract_mm = e.cycle.retract_mm;
    out.cycle.feed_mm_per_min = e.cycle.feed_mm_per_min;
    out.cycle.dwell_s = e.cycle.dwell_s;
    out.cycle.first_peck_mm = e.cycle.first_peck_mm;
    out.cycle.next_peck_mm = e.cycle.next_peck_mm;
    out.cycle.name = e.text.c_str();
    out.nurbs_knots = e.nurbs_knots.data();
    out.nurbs_knot_count = static_cast<int>(e.nurbs_knots.size());
    reader->nurbs_points.clear();
    for (const redpost::ClNurbsPoint& q : e.nurbs_points)
      reader->nurbs_points.insert(reader->nurbs_points.end(), {q.x, q.y, q.z, q.w});
    out.nurbs_points = reader->nurbs_points.data();
    out.nurbs_point_count = static_cast<int>(e.nurbs_points.size());
    for (int i = 0; i < 3; ++i) {
      out.msys_x[i] = e.msys_x[i];
      out.msys_y[i] = e.msys_y[i];
    }
    out.text_kind = e.text_kind == redpost::TextKind::pprint    ? RP_TEXT_PPRINT
                    : e.text_kind == redpost::TextKind::message ? RP_TEXT_MESSAGE
                                                                : RP_TEXT_INSERT;
    *event = out;
    *more = 1;
  });
  if (status != RP_OK && status != RP_ERR_NULL)
    reader->failed = status;
  return status;
}

RP_API const char* rp_reader_last_error(const rp_reader* reader) {
  return reader ? reader->error.c_str() : t_error.c_str();
}

RP_API const char* rp_reader_warning(const rp_reader* reader, int index) {
  if (!reader || index < 0)
    return nullptr;
  const std::deque<std::string>& w = reader->reader->warnings();
  return static_cast<std::size_t>(index) < w.size() ? w[static_cast<std::size_t>(index)].c_str()
                                                    : nullptr;
}

RP_API void rp_reader_free(rp_reader* reader) {
  delete reader;
}

RP_API rp_status rp_session_event(rp_session* session, const rp_event* event) {
  if (!session)
    return null_handle("the session");
  return session->event_at(event ? event->line : -1, [&] {
    if (!event)
      throw AbiError{RP_ERR_NULL, "the event is NULL"};
    redpost::ClEvent e;
    set_kind_of(*event, e);
    e.line = event->line;
    e.p_mm = vec(event->p[0], event->p[1], event->p[2]);
    e.tool_axis = vec(event->axis[0], event->axis[1], event->axis[2]);
    e.rapid = event->rapid != 0;
    e.tool_number = event->tool_number;
    e.tool_diameter_mm = event->tool_diameter_mm;
    e.tool_length_mm = event->tool_length_mm;
    e.value = event->value;
    switch (enum_value(event->direction)) {
      case RP_SPINDLE_OFF:
        e.direction = redpost::SpindleDirection::off;
        break;
      case RP_SPINDLE_CW:
        e.direction = redpost::SpindleDirection::clockwise;
        break;
      case RP_SPINDLE_CCW:
        e.direction = redpost::SpindleDirection::counter_clockwise;
        break;
      default:
        if (e.kind == redpost::ClEventKind::spindle)
          throw AbiError{RP_ERR_BAD_INPUT, "the spindle direction is not an rp_spindle_direction"};
    }
    e.flag = event->flag != 0;
    if (event->text)
      e.text = event->text;
    e.has_clearance = event->has_clearance != 0;
    e.clearance_p_mm = vec(event->clearance_p[0], event->clearance_p[1], event->clearance_p[2]);
    e.arc_centre_mm = vec(event->arc_centre[0], event->arc_centre[1], event->arc_centre[2]);
    e.arc_axis = vec(event->arc_axis[0], event->arc_axis[1], event->arc_axis[2]);
    // The fields added in 0.6, only for the kinds added with them.
    switch (enum_value(event->kind)) {
      case RP_EVENT_CYCLE:
        cycle_from(event->cycle, e);
        break;
      case RP_EVENT_NURBS:
        nurbs_from(event->nurbs_knots, event->nurbs_knot_count, event->nurbs_points,
                   event->nurbs_point_count, e);
        break;
      case RP_EVENT_MSYS:
        e.msys_x = vec(event->msys_x[0], event->msys_x[1], event->msys_x[2]);
        e.msys_y = vec(event->msys_y[0], event->msys_y[1], event->msys_y[2]);
        break;
      case RP_EVENT_OPERATOR_TEXT:
        if (!event->text)
          throw AbiError{RP_ERR_NULL, "the operator text is NULL"};
        e.text_kind = text_kind_of(event->text_kind);
        break;
      default:
        break;
    }
    session->submit(std::move(e));
  });
}

}  // extern "C"
