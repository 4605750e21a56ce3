// The streaming APT/CLDATA and NX CLSF reader (docs/cl-format.md): the public ClReader and the
// driving of its Impl (cl/reader_impl.hpp).
//
// One record at a time: ClRecordReader (cl/record.cpp) takes physical lines from ClLineSource,
// joins `$` continuations, strips `$$` comments and finds the major word, and one handler per
// word turns the record into toolpath events (cl/event.hpp). Without toolpath_events each goes
// through the reader's ClExpander, which gives out what an arc, a NURBS or a drilling cycle
// stands for one event at a time, so memory does not depend on how many chords an arc needs.
//
// This file reads the records, hands each to its handler and drives the expander; the handlers
// are in one file per kind of record: motion.cpp (the event queue; GOTO, FROM, GODLTA, RAPID,
// TLAXIS), arcs.cpp (CIRCLE), nurbs.cpp (NURBS, KNOT, CNTRL), cycles.cpp (CYCLE and its holes),
// settings.cpp (the records that only set machine state: feed, spindle, coolant, tools, units,
// MULTAX, MSYS, CSYS, TRNTYP, CUTCOM).
//
// Nothing here allocates per record once the buffers have grown to the longest record: the
// record, its fields (string_views into it) and the event queue are reused, and numbers are
// read with std::from_chars.
#include "redpost/cl/reader.hpp"

#include <cmath>
#include <string>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "cl/reader_impl.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

ClReader::Impl::Impl(std::istream& in, std::string source_name, ClReaderOptions options)
    : ClRecordReader(in, std::move(source_name), options.max_line_bytes, options.keep_comments),
      opt(options),
      nx(options.dialect == ClDialect::nx_clsf) {
  if (const std::string why = chordal_tolerance_problem(opt.chordal_tolerance_mm); !why.empty())
    throw Error(ErrorCode::bad_input, why);
  if (!(opt.point_match_tolerance_mm > 0.0) || !std::isfinite(opt.point_match_tolerance_mm))
    throw Error(ErrorCode::bad_input, "point match tolerance must be a positive number of mm");
  queue.reserve(16);
  if (!opt.toolpath_events) {
    ClExpanderOptions eo;
    eo.chordal_tolerance_mm = opt.chordal_tolerance_mm;
    eo.point_match_tolerance_mm = opt.point_match_tolerance_mm;
    eo.msys = opt.msys;
    eo.chord_arcs = !opt.arcs_as_events;
    expander = std::make_unique<ClExpander>(
        source, eo, [this](const std::string& w) { warnings.push_back(w); });
  }
}

void ClReader::Impl::warn_once(const std::string& key, int line_no, const std::string& message) {
  if (warned.insert(key).second)
    warnings.push_back(format_error(SourceLocation{source, line_no, 0}, message));
}

// ===========================================================================================
// Driving

// The next record: the one put back after a NURBS (record_pending), or the next of the file.
// False at the end.
bool ClReader::Impl::read_record() {
  if (record_pending) {
    record_pending = false;
    return true;
  }
  return next_record();
}

void ClReader::Impl::step() {
  if (!read_record()) {
    finish_input();
    return;
  }
  handle_record();
}

void ClReader::Impl::finish_input() {
  if (collecting_nurbs) {
    finish_nurbs();
    return;
  }
  if (arc_pending)
    fail_line(arc_line, "the file ends after CIRCLE without the GOTO that ends the arc");
  finished = true;
}

void ClReader::Impl::handle_record() {
  if (word.empty()) {
    emit_comments();
    return;
  }
  if (collecting_nurbs) {
    if (word == "KNOT") {
      on_knot();
    } else if (word == "CNTRL") {
      on_cntrl();
    } else {
      finish_nurbs();
      record_pending = true;  // handled once the curve's moves are out
      return;
    }
    emit_comments();
    return;
  }
  if (opt.dialect == ClDialect::automatic && !nx) {
    nx = word == "TOOL PATH" || word == "TLDATA" || word == "MSYS" || word == "END-OF-PATH" ||
         word == "PAINT";
  }
  if (arc_pending)
    check_arc_not_interrupted();
  dispatch();
  emit_comments();
}

void ClReader::Impl::emit_comments() {
  for (const std::string& c : comments)
    push(ClEventKind::comment, record_line).text = c;
}

void ClReader::Impl::dispatch() {
  const std::string& w = word;
  if (w == "GOTO") {
    on_goto(MoveOrigin::goto_point);
  } else if (w == "FROM") {
    on_goto(MoveOrigin::from_point);
  } else if (w == "GODLTA") {
    on_godlta();
  } else if (w == "RAPID") {
    on_rapid();
  } else if (w == "CIRCLE") {
    on_circle();
  } else if (w == "NURBS") {
    on_nurbs();
  } else if (w == "KNOT" || w == "CNTRL") {
    fail_word(w + "/ outside a NURBS/ block (it must follow NURBS/ or another KNOT/ or CNTRL/)");
  } else if (w == "CYCLE") {
    on_cycle();
  } else if (w == "FEDRAT") {
    on_fedrat();
  } else if (w == "SPINDL") {
    on_spindl();
  } else if (w == "COOLNT") {
    on_coolnt();
  } else if (w == "LOADTL") {
    on_loadtl();
  } else if (w == "LOAD") {
    on_load_or_select(true);
  } else if (w == "SELECT") {
    on_load_or_select(false);
  } else if (w == "CUTTER") {
    on_cutter();
  } else if (w == "TLDATA") {
    on_tldata();
  } else if (w == "TOOL PATH") {
    on_tool_path();
  } else if (w == "END-OF-PATH") {
    push(ClEventKind::operation_end, record_line);
  } else if (w == "PARTNO") {
    push_text(ClEventKind::part_name, trim(raw_args()));
  } else if (w == "PPRINT") {
    on_operator_text(false);
  } else if (w == "INSERT") {
    on_operator_text(true);
  } else if (w == "UNITS" || w == "UNIT") {
    on_units();
  } else if (w == "MULTAX") {
    on_multax();
  } else if (w == "TLAXIS") {
    on_tlaxis();
  } else if (w == "MSYS") {
    on_msys();
  } else if (w == "CSYS") {
    on_csys();
  } else if (w == "TRNTYP") {
    on_trntyp();
  } else if (w == "CUTCOM") {
    on_cutcom();
  } else if (w == "PAINT") {
    // NX display colours and speeds for the toolpath replay: nothing for a robot.
  } else if (w == "END" || w == "FINI") {
    push(ClEventKind::end_of_program, record_line);
  } else if (w == "ORIGIN" || w == "TRANS" || w == "ROTABL" || w == "COPY" || w == "INDEX") {
    fail_word(w +
              " is not supported: it moves the coordinate system or repeats records, and "
              "ignoring it would put every following point in the wrong place");
  } else {
    on_unknown();
  }
}

void ClReader::Impl::on_unknown() {
  if (unknown_words.find(word) != unknown_words.end())
    return;
  // A file of garbage words must not grow the warnings without bound.
  constexpr std::size_t kMaxUnknownWords = 1000;
  if (unknown_words.size() >= kMaxUnknownWords) {
    warn_once("many unknown words", record_line,
              "more than " + std::to_string(kMaxUnknownWords) +
                  " different unknown words; the others are ignored without a warning");
    return;
  }
  unknown_words.insert(word);
  warnings.push_back(
      format_error(SourceLocation{source, record_line, 0}, "unknown word " + word + " ignored"));
  push(ClEventKind::unknown_word, record_line).text = word;
}

// INSERT and PPRINT carry operator text (tool holders, stock sizes, notes): what becomes of it
// (a comment, or INSERT/KRL:'s statement) is the expander's business, the same for NX's texts.
void ClReader::Impl::on_operator_text(bool insert) {
  ClEvent& e = push(ClEventKind::operator_text, record_line);
  const std::string_view text = trim(raw_args());
  e.text.assign(text.data(), text.size());
  e.text_kind = insert ? TextKind::insert : TextKind::pprint;
}

// ===========================================================================================
// ClReader

ClReader::ClReader(std::istream& in, std::string source_name, ClReaderOptions options)
    : impl_(std::make_unique<Impl>(in, std::move(source_name), options)) {}

ClReader::~ClReader() = default;

bool ClReader::next(ClEvent& event) {
  Impl& m = *impl_;
  try {
    for (;;) {
      if (m.expander && m.expander->next(event))
        return true;
      if (m.head < m.queue.size()) {
        ClEvent& e = m.queue[m.head++];
        if (!m.expander) {
          event = std::move(e);
          return true;
        }
        m.expander->push(e);
        continue;
      }
      if (m.finished)
        return false;
      m.queue.clear();
      m.head = 0;
      m.step();
    }
  } catch (...) {
    // After an error the stream position is inside a broken record: stop for good.
    m.finished = true;
    m.queue.clear();
    m.head = 0;
    m.expander.reset();  // what it had left is dropped with it
    throw;
  }
}

const std::deque<std::string>& ClReader::warnings() const {
  return impl_->warnings;
}

const std::string& ClReader::source_name() const {
  return impl_->source;
}

}  // namespace redpost
