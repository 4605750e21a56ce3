// The Tcl package's commands for the rest of the toolpath (redpost.h, "Added in 0.6"): drilling
// cycles and their holes, NURBS, NX's MSYS, dwells, cutter compensation, operator text and the
// host's warnings, one to one onto the C ABI, for the NX handlers (tcl/redpost_post.tcl).
#include <tcl.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "redpost.h"
#include "tcl_args.hpp"
#include "tcl_state.hpp"

#ifndef TCL_SIZE_MAX
typedef int Tcl_Size;  // Tcl 8.6
#endif

namespace redpost::tcl {

namespace {

int usage_error(Tcl_Interp* interp, const std::string& message) {
  Tcl_SetObjResult(interp, Tcl_NewStringObj(message.c_str(), -1));
  Tcl_SetErrorCode(interp, "REDPOST", "USAGE", static_cast<char*>(nullptr));
  return TCL_ERROR;
}

// n doubles from objv, named for the usage message.
int get_doubles(Tcl_Interp* interp, Tcl_Obj* const objv[], const char* const names[], int n,
                double* out) {
  for (int k = 0; k < n; ++k) {
    if (get_double(interp, objv[k], names[k], &out[k]) != TCL_OK)
      return TCL_ERROR;
  }
  return TCL_OK;
}

// A list of numbers (a NURBS's knots or points, a vector of 3).
int get_number_list(Tcl_Interp* interp, Tcl_Obj* list, const char* what, std::vector<double>& out) {
  Tcl_Size n = 0;
  Tcl_Obj** items = nullptr;
  if (Tcl_ListObjGetElements(interp, list, &n, &items) != TCL_OK)
    return TCL_ERROR;
  out.resize(static_cast<std::size_t>(n));
  for (Tcl_Size k = 0; k < n; ++k) {
    if (get_double(interp, items[k], what, &out[static_cast<std::size_t>(k)]) != TCL_OK)
      return TCL_ERROR;
  }
  return TCL_OK;
}

int get_vector3(Tcl_Interp* interp, Tcl_Obj* list, const char* what, double out[3]) {
  std::vector<double> v;
  if (get_number_list(interp, list, what, v) != TCL_OK)
    return TCL_ERROR;
  if (v.size() != 3)
    return usage_error(interp, std::string(what) + " takes three numbers {x y z}");
  for (int k = 0; k < 3; ++k)
    out[k] = v[static_cast<std::size_t>(k)];
  return TCL_OK;
}

// ::redpost::cycle s ?-peck 0|1? -depth MM -clearance MM ?-retract MM? ?-feed MM/MIN?
//     ?-dwell S? ?-first-peck MM? ?-next-peck MM? ?-name TEXT?
int cmd_cycle(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  if (objc < 2 || objc % 2 != 0) {
    return usage(interp, objv,
                 "session ?-peck 0|1? -depth MM -clearance MM ?-retract MM? ?-feed MM/MIN? "
                 "?-dwell S? ?-first-peck MM? ?-next-peck MM? ?-name TEXT?");
  }
  rp_session* s = nullptr;
  if (get_session(interp, STATE, objv[1], &s) != TCL_OK)
    return TCL_ERROR;
  static const char* const kOptions[] = {"-peck", "-depth", "-clearance",  "-retract",
                                         "-feed", "-dwell", "-first-peck", "-next-peck",
                                         "-name", nullptr};
  rp_cycle_params p;
  rp_cycle_params_init(&p);
  double* const values[] = {nullptr,          &p.depth_mm,        &p.clearance_mm,
                            &p.retract_mm,    &p.feed_mm_per_min, &p.dwell_s,
                            &p.first_peck_mm, &p.next_peck_mm};
  for (int i = 2; i < objc; i += 2) {
    int k = 0;
    if (Tcl_GetIndexFromObj(interp, objv[i], kOptions, "option", 0, &k) != TCL_OK)
      return TCL_ERROR;
    if (k == 0) {
      if (Tcl_GetBooleanFromObj(interp, objv[i + 1], &p.peck) != TCL_OK)
        return TCL_ERROR;
    } else if (k == 8) {
      if (get_text(interp, objv[i + 1], "cycle name", &p.name) != TCL_OK)
        return TCL_ERROR;
    } else if (*Tcl_GetString(objv[i + 1]) != '\0') {  // empty: not given
      if (get_double(interp, objv[i + 1], kOptions[k], values[k]) != TCL_OK)
        return TCL_ERROR;
    }
  }
  return session_result(interp, s, rp_cycle_define(s, &p));
}

int cmd_cycle_hole(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(6, "x y z i j k")
  static const char* const kNames[] = {"x", "y", "z", "i", "j", "k"};
  double v[6];
  if (get_doubles(interp, objv + 2, kNames, 6, v) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_cycle_hole(s, v[0], v[1], v[2], v[3], v[4], v[5]));
}

int cmd_cycle_on(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  return session_result(interp, s, rp_cycle_on(s));
}

int cmd_cycle_off(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(0, "")
  return session_result(interp, s, rp_cycle_off(s));
}

// ::redpost::nurbs_move s KNOTS POINTS i j k: POINTS a flat list of x y z w per control point.
int cmd_nurbs_move(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(5, "knots points i j k")
  std::vector<double> knots, points;
  if (get_number_list(interp, objv[2], "knots", knots) != TCL_OK ||
      get_number_list(interp, objv[3], "points", points) != TCL_OK)
    return TCL_ERROR;
  if (points.size() % 4 != 0)
    return usage_error(interp, "points takes x y z w for every control point (4 numbers each)");
  static const char* const kNames[] = {"i", "j", "k"};
  double a[3];
  if (get_doubles(interp, objv + 4, kNames, 3, a) != TCL_OK)
    return TCL_ERROR;
  constexpr std::size_t kMost = static_cast<std::size_t>(std::numeric_limits<int>::max() / 4);
  if (knots.size() > kMost || points.size() / 4 > kMost)
    return usage_error(interp, "too many knots or points");
  return session_result(
      interp, s,
      rp_nurbs_move(s, knots.data(), static_cast<int>(knots.size()), points.data(),
                    static_cast<int>(points.size() / 4), a[0], a[1], a[2]));
}

// ::redpost::machine_frame s {ox oy oz} {xi xj xk} {yi yj yk}
int cmd_machine_frame(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(3, "origin x_axis y_axis")
  double origin[3], x[3], y[3];
  if (get_vector3(interp, objv[2], "origin", origin) != TCL_OK ||
      get_vector3(interp, objv[3], "x_axis", x) != TCL_OK ||
      get_vector3(interp, objv[4], "y_axis", y) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_machine_frame(s, origin, x, y));
}

int cmd_dwell(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(1, "seconds")
  double seconds = 0;
  if (get_double(interp, objv[2], "seconds", &seconds) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_dwell(s, seconds));
}

int cmd_cutcom(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(2, "on side")
  int on = 0;
  const char* side = nullptr;
  if (Tcl_GetBooleanFromObj(interp, objv[2], &on) != TCL_OK ||
      get_text(interp, objv[3], "side", &side) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_cutcom(s, on, side));
}

int cmd_operator_text(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(2, "insert|pprint|message text")
  static const char* const kKinds[] = {"insert", "pprint", "message", nullptr};
  static const rp_text_kind kMap[] = {RP_TEXT_INSERT, RP_TEXT_PPRINT, RP_TEXT_MESSAGE};
  int k = 0;
  const char* text = nullptr;
  if (Tcl_GetIndexFromObj(interp, objv[2], kKinds, "kind", 0, &k) != TCL_OK ||
      get_text(interp, objv[3], "text", &text) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_operator_text(s, kMap[k], text));
}

int cmd_warn(ClientData cd, Tcl_Interp* interp, int objc, Tcl_Obj* const objv[]) {
  SESSION_ARGS(1, "text")
  const char* text = nullptr;
  if (get_text(interp, objv[2], "warning", &text) != TCL_OK)
    return TCL_ERROR;
  return session_result(interp, s, rp_warn(s, text));
}

}  // namespace

const Command kToolpathCommands[] = {
    {"::redpost::cycle", cmd_cycle},
    {"::redpost::cycle_hole", cmd_cycle_hole},
    {"::redpost::cycle_on", cmd_cycle_on},
    {"::redpost::cycle_off", cmd_cycle_off},
    {"::redpost::nurbs_move", cmd_nurbs_move},
    {"::redpost::machine_frame", cmd_machine_frame},
    {"::redpost::dwell", cmd_dwell},
    {"::redpost::cutcom", cmd_cutcom},
    {"::redpost::operator_text", cmd_operator_text},
    {"::redpost::warn", cmd_warn},
};
const int kToolpathCommandCount = sizeof kToolpathCommands / sizeof kToolpathCommands[0];

}  // namespace redpost::tcl
