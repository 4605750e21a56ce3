// The C ABI's CL reader (redpost.h): rp_reader_* over redpost::ClReader, and reader events sent
// to a session (rp_session_event), as `redpost convert` and the C host do for every event.
#include <cmath>
#include <cstring>
#include <deque>
#include <string>

#include <fmt/format.h>

#include "abi_internal.hpp"
#include "redpost/io/text_file.hpp"

using namespace redpost::abi;

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
    if (o.msys != RP_MSYS_IGNORE && o.msys != RP_MSYS_APPLY)
      throw AbiError{RP_ERR_BAD_INPUT, "msys is not RP_MSYS_IGNORE or RP_MSYS_APPLY"};
    r = std::make_unique<rp_reader>();
    r->in = redpost::open_text_stream(path);
    redpost::ClReaderOptions read;
    read.chordal_tolerance_mm = o.chordal_tolerance_mm;
    read.msys = o.msys == RP_MSYS_APPLY ? redpost::MsysMode::apply : redpost::MsysMode::ignore;
    read.arcs_as_events = o.arcs_as_events != 0;
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
    switch (e.kind) {
      case redpost::ClEventKind::part_name:
        out.kind = RP_EVENT_PART_NAME;
        break;
      case redpost::ClEventKind::tool_change:
        out.kind = RP_EVENT_TOOL_CHANGE;
        break;
      case redpost::ClEventKind::spindle:
        out.kind = RP_EVENT_SPINDLE;
        break;
      case redpost::ClEventKind::feed:
        out.kind = RP_EVENT_FEED;
        break;
      case redpost::ClEventKind::rapid:
        out.kind = RP_EVENT_RAPID;
        break;
      case redpost::ClEventKind::move:
        out.kind = RP_EVENT_MOVE;
        break;
      case redpost::ClEventKind::coolant:
        out.kind = RP_EVENT_COOLANT;
        break;
      case redpost::ClEventKind::operation_start:
        out.kind = RP_EVENT_OPERATION_START;
        break;
      case redpost::ClEventKind::operation_end:
        out.kind = RP_EVENT_OPERATION_END;
        break;
      case redpost::ClEventKind::comment:
        out.kind = RP_EVENT_COMMENT;
        break;
      case redpost::ClEventKind::literal:
        out.kind = RP_EVENT_LITERAL;
        break;
      case redpost::ClEventKind::unknown_word:
        out.kind = RP_EVENT_UNKNOWN_WORD;
        break;
      case redpost::ClEventKind::end_of_program:
        out.kind = RP_EVENT_END_OF_PROGRAM;
        break;
      case redpost::ClEventKind::dwell:
        out.kind = RP_EVENT_DWELL;
        break;
      case redpost::ClEventKind::machine_frame:
        out.kind = RP_EVENT_MACHINE_FRAME;
        break;
      case redpost::ClEventKind::arc:
        out.kind = RP_EVENT_ARC;
        break;
    }
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
  return session->event([&] {
    if (!event)
      throw AbiError{RP_ERR_NULL, "the event is NULL"};
    redpost::ClEvent e;
    switch (event->kind) {
      case RP_EVENT_PART_NAME:
        e.kind = redpost::ClEventKind::part_name;
        break;
      case RP_EVENT_TOOL_CHANGE:
        e.kind = redpost::ClEventKind::tool_change;
        break;
      case RP_EVENT_SPINDLE:
        e.kind = redpost::ClEventKind::spindle;
        break;
      case RP_EVENT_FEED:
        e.kind = redpost::ClEventKind::feed;
        break;
      case RP_EVENT_RAPID:
        e.kind = redpost::ClEventKind::rapid;
        break;
      case RP_EVENT_MOVE:
        e.kind = redpost::ClEventKind::move;
        break;
      case RP_EVENT_COOLANT:
        e.kind = redpost::ClEventKind::coolant;
        break;
      case RP_EVENT_OPERATION_START:
        e.kind = redpost::ClEventKind::operation_start;
        break;
      case RP_EVENT_OPERATION_END:
        e.kind = redpost::ClEventKind::operation_end;
        break;
      case RP_EVENT_COMMENT:
        e.kind = redpost::ClEventKind::comment;
        break;
      case RP_EVENT_LITERAL:
        e.kind = redpost::ClEventKind::literal;
        break;
      case RP_EVENT_UNKNOWN_WORD:
        e.kind = redpost::ClEventKind::unknown_word;
        break;
      case RP_EVENT_END_OF_PROGRAM:
        e.kind = redpost::ClEventKind::end_of_program;
        break;
      case RP_EVENT_DWELL:
        e.kind = redpost::ClEventKind::dwell;
        break;
      case RP_EVENT_MACHINE_FRAME:
        e.kind = redpost::ClEventKind::machine_frame;
        break;
      case RP_EVENT_ARC:
        e.kind = redpost::ClEventKind::arc;
        break;
      default:
        throw AbiError{RP_ERR_BAD_INPUT, "event kind " +
                                             std::to_string(static_cast<int>(event->kind)) +
                                             " is not an rp_event_kind"};
    }
    e.line = event->line;
    e.p_mm = vec(event->p[0], event->p[1], event->p[2]);
    e.tool_axis = vec(event->axis[0], event->axis[1], event->axis[2]);
    e.rapid = event->rapid != 0;
    e.tool_number = event->tool_number;
    e.tool_diameter_mm = event->tool_diameter_mm;
    e.tool_length_mm = event->tool_length_mm;
    e.value = event->value;
    switch (event->direction) {
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
    session->post->handle(e);
  });
}

}  // extern "C"
