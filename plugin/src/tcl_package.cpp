// The Tcl package "redpost": Tcl commands in ::redpost:: that map one to one onto the C ABI
// (redpost.h), for the NX event handlers (tcl/redpost_post.tcl) and any Tcl host.
//
// Sessions and readers live in a per-interpreter table (assoc data) under handles such as "rp0"
// and "rpreader1"; whatever is left in it is freed when the interpreter is deleted. Every status
// other than RP_OK becomes a Tcl error with rp_last_error's message and the errorCode
// {REDPOST RP_ERR_...}. Wrong arguments are Tcl errors with a usage message.
//
// The library is built against the Tcl stubs table when USE_TCL_STUBS is defined, so that it
// loads into any Tcl 8.6 (NX's own tclsh included).
#include <tcl.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "redpost.h"
#include "tcl_args.hpp"
#include "tcl_open_options.hpp"
#include "tcl_state.hpp"

#ifndef TCL_SIZE_MAX
typedef int Tcl_Size;  // Tcl 8.6
#endif

namespace {

using redpost::tcl::get_double;
using redpost::tcl::get_int;
using redpost::tcl::get_text;
using redpost::tcl::kOpenOptions;
using redpost::tcl::kOpenUsage;
using redpost::tcl::open_option;
using namespace redpost::tcl;

int cmd_version(ClientData, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  if (objc != 1)
    return usage(interp, objv, "");
  Tcl_SetObjResult(interp, Tcl_NewStringObj(rp_version(), -1));
  return TCL_OK;
}

int cmd_open(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  if (objc % 2 != 1)
    return usage(interp, objv, kOpenUsage);
  rp_options opt;
  rp_options_init(&opt);
  redpost::tcl::OpenStorage storage;
  // The strings stay owned by objv for the duration of rp_open.
  for (int i = 1; i < objc; i += 2) {
    int index = 0;
    if (Tcl_GetIndexFromObj(interp, objv[i], kOpenOptions, "option", 0, &index) != TCL_OK)
      return TCL_ERROR;
    if (open_option(interp, index, objv[i + 1], opt, storage) != TCL_OK)
      return TCL_ERROR;
  }
  if (!opt.cell_path || !opt.output_dir || !opt.program_name) {
    Tcl_SetObjResult(
        interp, Tcl_ObjPrintf("%s needs -cell, -output and -name: %s %s", Tcl_GetString(objv[0]),
                              Tcl_GetString(objv[0]), kOpenUsage));
    Tcl_SetErrorCode(interp, "REDPOST", "USAGE", static_cast<char*>(nullptr));
    return TCL_ERROR;
  }
  rp_session* s = nullptr;
  const rp_status st = rp_open(&opt, &s);
  if (st != RP_OK || !s)
    return fail(interp, st == RP_OK ? RP_ERR_INTERNAL : st, rp_last_error(nullptr));
  const std::string handle = "rp" + std::to_string(STATE->next_id++);
  STATE->sessions[handle] = s;
  Tcl_SetObjResult(interp, Tcl_NewStringObj(handle.c_str(), -1));
  return TCL_OK;
}

int cmd_set_line(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(1, "line")
  int line = 0;
  if (get_int(interp, objv[2], "line", &line) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_set_line(s, line));
}

int cmd_tool_change(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(4, "number name diameter length")
  int number = 0;
  double d = 0, l = 0;
  const char* name = nullptr;
  if (get_int(interp, objv[2], "number", &number) != TCL_OK ||
      get_text(interp, objv[3], "tool name", &name) != TCL_OK ||
      get_double(interp, objv[4], "diameter", &d) != TCL_OK ||
      get_double(interp, objv[5], "length", &l) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_tool_change(s, number, name, d, l));
}

int cmd_spindle(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(2, "rpm CW|CCW|OFF")
  static const char* const kDirections[] = {"OFF", "CW", "CCW", nullptr};
  double rpm = 0;
  int dir = 0;
  if (get_double(interp, objv[2], "rpm", &rpm) != TCL_OK ||
      Tcl_GetIndexFromObj(interp, objv[3], kDirections, "direction", 0, &dir) != TCL_OK)
    return TCL_ERROR;
  static const rp_spindle_direction kMap[] = {RP_SPINDLE_OFF, RP_SPINDLE_CW, RP_SPINDLE_CCW};
  return session_result(interp, s, rp_spindle(s, rpm, kMap[dir]));
}

int cmd_feed(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(1, "mm_per_min")
  double f = 0;
  if (get_double(interp, objv[2], "mm_per_min", &f) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_feed(s, f));
}

int cmd_rapid(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  return session_result(interp, s, rp_rapid(s));
}

int get_doubles(Tcl_Interp* interp, Tcl_Obj* const objv[], const char* const names[], int n,
                double* out) {
  for (int k = 0; k < n; ++k) {
    if (get_double(interp, objv[k], names[k], &out[k]) != TCL_OK)
      return TCL_ERROR;
  }
  return TCL_OK;
}

// ::redpost::linear_move s x y z i j k ?line?: with the line, rp_set_line first (one call per
// motion for the NX handlers).
int cmd_linear_move(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  if (objc != 8 && objc != 9)
    return usage(interp, objv, "session x y z i j k ?line?");
  rp_session* s = nullptr;
  if (get_session(interp, STATE, objv[1], &s) != TCL_OK)
    return TCL_ERROR;
  static const char* const kNames[] = {"x", "y", "z", "i", "j", "k"};
  double v[6];
  if (get_doubles(interp, objv + 2, kNames, 6, v) != TCL_OK)
    return TCL_ERROR;
  if (objc == 9) {
    int line = 0;
    if (get_int(interp, objv[8], "line", &line) != TCL_OK)
      return TCL_ERROR;
    if (const rp_status st = rp_set_line(s, line); st != RP_OK)
      return session_result(interp, s, st);
  }
  return session_result(interp, s, rp_linear_move(s, v[0], v[1], v[2], v[3], v[4], v[5]));
}

int cmd_circular_move(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(13, "cx cy cz ax ay az radius x y z i j k")
  static const char* const kNames[] = {"cx", "cy", "cz", "ax", "ay", "az", "radius",
                                       "x",  "y",  "z",  "i",  "j",  "k"};
  double v[13];
  if (get_doubles(interp, objv + 2, kNames, 13, v) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s,
                        rp_circular_move(s, v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8],
                                         v[9], v[10], v[11], v[12]));
}

int cmd_operation_start(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(1, "name")
  const char* text = nullptr;
  if (get_text(interp, objv[2], "operation name", &text) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_operation_start(s, text));
}

int cmd_operation_end(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  return session_result(interp, s, rp_operation_end(s));
}

int cmd_coolant(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(2, "on mode")
  int on = 0;
  if (Tcl_GetBooleanFromObj(interp, objv[2], &on) != TCL_OK)
    return TCL_ERROR;
  const char* text = nullptr;
  if (get_text(interp, objv[3], "coolant mode", &text) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_coolant(s, on, text));
}

int cmd_comment(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(1, "text")
  const char* text = nullptr;
  if (get_text(interp, objv[2], "comment", &text) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_comment(s, text));
}

int cmd_literal(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(1, "text")
  const char* text = nullptr;
  if (get_text(interp, objv[2], "literal", &text) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_literal(s, text));
}

int cmd_close(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  return session_result(interp, s, rp_close(s));
}

int cmd_free(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  STATE->sessions.erase(Tcl_GetString(objv[1]));
  rp_free(s);
  Tcl_ResetResult(interp);
  return TCL_OK;
}

Tcl_Obj* double_list(const double* v, int n) {
  Tcl_Obj* list = Tcl_NewListObj(0, nullptr);
  for (int k = 0; k < n; ++k)
    Tcl_ListObjAppendElement(nullptr, list, Tcl_NewDoubleObj(v[k]));
  return list;
}

void put(Tcl_Obj* dict, const char* key, Tcl_Obj* value) {
  Tcl_DictObjPut(nullptr, dict, Tcl_NewStringObj(key, -1), value);
}

int cmd_last_move(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  rp_move_info info;
  std::memset(&info, 0, sizeof info);
  const rp_status st = rp_last_move(s, &info);
  if (st != RP_OK)
    return fail(interp, st, rp_last_error(s));
  const int n = info.joint_count < 0 ? 0 : (info.joint_count > 16 ? 16 : info.joint_count);
  Tcl_Obj* d = Tcl_NewDictObj();
  put(d, "joint_count", Tcl_NewIntObj(info.joint_count));
  put(d, "joints", double_list(info.joints, n));
  put(d, "axes", double_list(info.axes, 12));
  put(d, "inv_condition", Tcl_NewDoubleObj(info.inv_condition));
  put(d, "iterations", Tcl_NewIntObj(info.iterations));
  put(d, "position_error_mm", Tcl_NewDoubleObj(info.position_error_mm));
  put(d, "orientation_error_rad", Tcl_NewDoubleObj(info.orientation_error_rad));
  put(d, "limit_margin", Tcl_NewDoubleObj(info.limit_margin));
  Tcl_SetObjResult(interp, d);
  return TCL_OK;
}

int cmd_summary(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  rp_summary sum;
  std::memset(&sum, 0, sizeof sum);
  const rp_status st = rp_summary_get(s, &sum);
  if (st != RP_OK)
    return fail(interp, st, rp_last_error(s));
  Tcl_Obj* d = Tcl_NewDictObj();
  put(d, "poses", Tcl_NewWideIntObj(sum.poses));
  put(d, "motions", Tcl_NewWideIntObj(sum.motions));
  put(d, "lowest_inv_condition", Tcl_NewDoubleObj(sum.lowest_inv_condition));
  put(d, "lowest_inv_condition_line", Tcl_NewIntObj(sum.lowest_inv_condition_line));
  put(d, "warnings", Tcl_NewIntObj(sum.warnings));
  Tcl_Obj* files = Tcl_NewListObj(0, nullptr);
  for (int k = 0;; ++k) {
    const char* f = rp_output_file(s, k);
    if (!f)
      break;
    Tcl_ListObjAppendElement(nullptr, files, Tcl_NewStringObj(f, -1));
  }
  put(d, "files", files);
  Tcl_SetObjResult(interp, d);
  return TCL_OK;
}

int cmd_warnings(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  Tcl_Obj* list = Tcl_NewListObj(0, nullptr);
  for (int k = 0;; ++k) {
    const char* w = rp_warning(s, k);
    if (!w)
      break;
    Tcl_ListObjAppendElement(nullptr, list, Tcl_NewStringObj(w, -1));
  }
  Tcl_SetObjResult(interp, list);
  return TCL_OK;
}

int cmd_output_files(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  Tcl_Obj* list = Tcl_NewListObj(0, nullptr);
  for (int k = 0;; ++k) {
    const char* f = rp_output_file(s, k);
    if (!f)
      break;
    Tcl_ListObjAppendElement(nullptr, list, Tcl_NewStringObj(f, -1));
  }
  Tcl_SetObjResult(interp, list);
  return TCL_OK;
}

// --- reader -------------------------------------------------------------------------------------

int cmd_reader_open(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  if (objc < 2 || objc > 4)
    return usage(interp, objv, "path ?chordal_tolerance_mm? ?msys (ignore|apply)?");
  rp_reader_options ro;
  rp_reader_options_init(&ro);
  if (objc >= 3 &&
      get_double(interp, objv[2], "chordal_tolerance_mm", &ro.chordal_tolerance_mm) != TCL_OK)
    return TCL_ERROR;
  if (objc == 4) {
    static const char* const kMsys[] = {"ignore", "apply", nullptr};
    int m = 0;
    if (Tcl_GetIndexFromObj(interp, objv[3], kMsys, "msys mode", 0, &m) != TCL_OK)
      return TCL_ERROR;
    ro.msys = m == 1 ? RP_MSYS_APPLY : RP_MSYS_IGNORE;
  }
  rp_reader* r = nullptr;
  const rp_status st = rp_reader_open_ex(Tcl_GetString(objv[1]), &ro, &r);
  if (st != RP_OK || !r)
    return fail(interp, st == RP_OK ? RP_ERR_INTERNAL : st, rp_last_error(nullptr));
  const std::string handle = "rpreader" + std::to_string(STATE->next_id++);
  STATE->readers[handle] = r;
  Tcl_SetObjResult(interp, Tcl_NewStringObj(handle.c_str(), -1));
  return TCL_OK;
}

const char* event_kind_name(rp_event_kind k) {
  switch (k) {
    case RP_EVENT_PART_NAME:
      return "part_name";
    case RP_EVENT_TOOL_CHANGE:
      return "tool_change";
    case RP_EVENT_SPINDLE:
      return "spindle";
    case RP_EVENT_FEED:
      return "feed";
    case RP_EVENT_RAPID:
      return "rapid";
    case RP_EVENT_MOVE:
      return "move";
    case RP_EVENT_COOLANT:
      return "coolant";
    case RP_EVENT_OPERATION_START:
      return "operation_start";
    case RP_EVENT_OPERATION_END:
      return "operation_end";
    case RP_EVENT_COMMENT:
      return "comment";
    case RP_EVENT_LITERAL:
      return "literal";
    case RP_EVENT_UNKNOWN_WORD:
      return "unknown_word";
    case RP_EVENT_END_OF_PROGRAM:
      return "end_of_program";
    case RP_EVENT_DWELL:
      return "dwell";
    case RP_EVENT_MACHINE_FRAME:
      return "machine_frame";
    case RP_EVENT_ARC:
      return "arc";
    case RP_EVENT_CYCLE:
      return "cycle";
    case RP_EVENT_CYCLE_ON:
      return "cycle_on";
    case RP_EVENT_CYCLE_OFF:
      return "cycle_off";
    case RP_EVENT_HOLE:
      return "hole";
    case RP_EVENT_NURBS:
      return "nurbs";
    case RP_EVENT_MSYS:
      return "msys";
    case RP_EVENT_OPERATOR_TEXT:
      return "operator_text";
    case RP_EVENT_CUTCOM:
      return "cutcom";
    case RP_EVENT_FROM:
      return "from";
    case RP_EVENT_GODLTA:
      return "godlta";
  }
  return "unknown";
}

const char* direction_name(rp_spindle_direction d) {
  switch (d) {
    case RP_SPINDLE_CW:
      return "CW";
    case RP_SPINDLE_CCW:
      return "CCW";
    case RP_SPINDLE_OFF:
      break;
  }
  return "OFF";
}

// The event as a dict with every field of rp_event (keys as in redpost.h).
int cmd_reader_next(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  if (objc != 2)
    return usage(interp, objv, "reader");
  rp_reader* r = nullptr;
  if (get_reader(interp, STATE, objv[1], &r) != TCL_OK)
    return TCL_ERROR;
  rp_event e;
  std::memset(&e, 0, sizeof e);
  int more = 0;
  const rp_status st = rp_reader_next(r, &e, &more);
  if (st != RP_OK)
    return fail(interp, st, rp_reader_last_error(r));
  if (!more) {
    Tcl_ResetResult(interp);
    return TCL_OK;
  }
  Tcl_Obj* d = Tcl_NewDictObj();
  put(d, "kind", Tcl_NewStringObj(event_kind_name(e.kind), -1));
  put(d, "line", Tcl_NewIntObj(e.line));
  put(d, "p", double_list(e.p, 3));
  put(d, "axis", double_list(e.axis, 3));
  put(d, "rapid", Tcl_NewIntObj(e.rapid));
  put(d, "tool_number", Tcl_NewIntObj(e.tool_number));
  put(d, "tool_diameter_mm", Tcl_NewDoubleObj(e.tool_diameter_mm));
  put(d, "tool_length_mm", Tcl_NewDoubleObj(e.tool_length_mm));
  put(d, "value", Tcl_NewDoubleObj(e.value));
  put(d, "direction", Tcl_NewStringObj(direction_name(e.direction), -1));
  put(d, "flag", Tcl_NewIntObj(e.flag));
  put(d, "text", Tcl_NewStringObj(e.text ? e.text : "", -1));
  put(d, "has_clearance", Tcl_NewIntObj(e.has_clearance));
  put(d, "clearance_p", double_list(e.clearance_p, 3));
  put(d, "arc_centre", double_list(e.arc_centre, 3));
  put(d, "arc_axis", double_list(e.arc_axis, 3));
  Tcl_SetObjResult(interp, d);
  return TCL_OK;
}

int cmd_reader_warnings(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  if (objc != 2)
    return usage(interp, objv, "reader");
  rp_reader* r = nullptr;
  if (get_reader(interp, STATE, objv[1], &r) != TCL_OK)
    return TCL_ERROR;
  Tcl_Obj* list = Tcl_NewListObj(0, nullptr);
  for (int k = 0;; ++k) {
    const char* w = rp_reader_warning(r, k);
    if (!w)
      break;
    Tcl_ListObjAppendElement(nullptr, list, Tcl_NewStringObj(w, -1));
  }
  Tcl_SetObjResult(interp, list);
  return TCL_OK;
}

int cmd_reader_free(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  if (objc != 2)
    return usage(interp, objv, "reader");
  rp_reader* r = nullptr;
  if (get_reader(interp, STATE, objv[1], &r) != TCL_OK)
    return TCL_ERROR;
  STATE->readers.erase(Tcl_GetString(objv[1]));
  rp_reader_free(r);
  Tcl_ResetResult(interp);
  return TCL_OK;
}

const Command kCommands[] = {
    {"::redpost::open", cmd_open},
    {"::redpost::set_line", cmd_set_line},
    {"::redpost::tool_change", cmd_tool_change},
    {"::redpost::spindle", cmd_spindle},
    {"::redpost::feed", cmd_feed},
    {"::redpost::rapid", cmd_rapid},
    {"::redpost::linear_move", cmd_linear_move},
    {"::redpost::circular_move", cmd_circular_move},
    {"::redpost::operation_start", cmd_operation_start},
    {"::redpost::operation_end", cmd_operation_end},
    {"::redpost::coolant", cmd_coolant},
    {"::redpost::comment", cmd_comment},
    {"::redpost::literal", cmd_literal},
    {"::redpost::close", cmd_close},
    {"::redpost::free", cmd_free},
    {"::redpost::last_move", cmd_last_move},
    {"::redpost::summary", cmd_summary},
    {"::redpost::warnings", cmd_warnings},
    {"::redpost::output_files", cmd_output_files},
    {"::redpost::reader_open", cmd_reader_open},
    {"::redpost::reader_next", cmd_reader_next},
    {"::redpost::reader_warnings", cmd_reader_warnings},
    {"::redpost::reader_free", cmd_reader_free},
};

int init(Tcl_Interp* interp, bool safe) {
#ifdef USE_TCL_STUBS
  if (Tcl_InitStubs(interp, "8.6", 0) == nullptr)
    return TCL_ERROR;
#endif
  if (!Tcl_CreateNamespace(interp, "::redpost", nullptr, nullptr))
    return TCL_ERROR;
  Tcl_CreateObjCommand(interp, "::redpost::version", cmd_version, nullptr, nullptr);
  // A safe interpreter gets the version only: every other command reads or writes files.
  if (!safe) {
    auto* state = static_cast<InterpState*>(Tcl_GetAssocData(interp, kAssocKey, nullptr));
    if (!state) {
      state = new InterpState;
      Tcl_SetAssocData(interp, kAssocKey, delete_state, state);
    }
    for (const Command& c : kCommands)
      Tcl_CreateObjCommand(interp, c.name, c.proc, state, nullptr);
    for (int k = 0; k < kToolpathCommandCount; ++k) {
      Tcl_CreateObjCommand(interp, kToolpathCommands[k].name, kToolpathCommands[k].proc, state,
                           nullptr);
    }
  }
  return Tcl_PkgProvide(interp, "redpost", REDPOST_VERSION);
}

}  // namespace

extern "C" RP_API int Redpost_Init(Tcl_Interp* interp) {
  return init(interp, false);
}

extern "C" RP_API int Redpost_SafeInit(Tcl_Interp* interp) {
  return init(interp, true);
}
