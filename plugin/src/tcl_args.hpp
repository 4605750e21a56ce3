// The argument readers of the Tcl package's commands (tcl_package.cpp): numbers the plugin
// judges itself (NaN and Inf reach the ABI, which names the event and line), integers, and text
// without Tcl's encoded NUL.
//
// Internal to the plugin; not installed.
#pragma once

#include <tcl.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace redpost::tcl {

// A double, or NaN/Inf spelled out, so that the plugin (not Tcl) judges the value and reports it
// with the event and line.
inline int get_double(Tcl_Interp* interp, Tcl_Obj* obj, const char* what, double* out) {
  if (Tcl_GetDoubleFromObj(nullptr, obj, out) == TCL_OK)
    return TCL_OK;
  const char* s = Tcl_GetString(obj);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s, &end);
  if (end != s && *end == '\0' && !std::isfinite(v)) {
    *out = v;
    return TCL_OK;
  }
  Tcl_SetObjResult(interp, Tcl_ObjPrintf("expected a number for %s but got \"%s\"", what, s));
  Tcl_SetErrorCode(interp, "REDPOST", "USAGE", static_cast<char*>(nullptr));
  return TCL_ERROR;
}

// A text argument. Tcl keeps a NUL inside a string as the bytes C0 80 (its modified UTF-8):
// passed on, they would land in the program as two stray bytes, so a NUL is refused here.
inline int get_text(Tcl_Interp* interp, Tcl_Obj* obj, const char* what, const char** out) {
  *out = Tcl_GetString(obj);
  if (std::strstr(*out, "\xC0\x80") == nullptr)
    return TCL_OK;
  Tcl_SetObjResult(interp, Tcl_ObjPrintf("the %s holds a NUL character (\\0), which a KRL "
                                         "program cannot carry: remove it",
                                         what));
  Tcl_SetErrorCode(interp, "REDPOST", "USAGE", static_cast<char*>(nullptr));
  return TCL_ERROR;
}

inline int get_int(Tcl_Interp* interp, Tcl_Obj* obj, const char* what, int* out) {
  if (Tcl_GetIntFromObj(nullptr, obj, out) == TCL_OK)
    return TCL_OK;
  Tcl_SetObjResult(
      interp, Tcl_ObjPrintf("expected an integer for %s but got \"%s\"", what, Tcl_GetString(obj)));
  Tcl_SetErrorCode(interp, "REDPOST", "USAGE", static_cast<char*>(nullptr));
  return TCL_ERROR;
}

}  // namespace redpost::tcl
