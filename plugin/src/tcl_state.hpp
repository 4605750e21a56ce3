// The Tcl package's per-interpreter state and the plumbing every command shares
// (tcl_package.cpp, tcl_toolpath.cpp): the handle tables, a status as a Tcl error with the
// errorCode {REDPOST RP_ERR_...}, the session and reader lookups.
//
// Internal to the plugin; not installed.
#pragma once

#include <tcl.h>

#include <map>
#include <string>

#include "redpost.h"

namespace redpost::tcl {

inline constexpr const char* kAssocKey = "redpost::state";

struct InterpState {
  std::map<std::string, rp_session*> sessions;
  std::map<std::string, rp_reader*> readers;
  unsigned long next_id = 0;
};

inline void delete_state(ClientData data, Tcl_Interp*) {
  auto* state = static_cast<InterpState*>(data);
  for (auto& s : state->sessions)
    rp_free(s.second);
  for (auto& r : state->readers)
    rp_reader_free(r.second);
  delete state;
}

inline const char* status_name(rp_status s) {
  switch (s) {
    case RP_OK:
      return "RP_OK";
    case RP_ERR_BAD_INPUT:
      return "RP_ERR_BAD_INPUT";
    case RP_ERR_IO:
      return "RP_ERR_IO";
    case RP_ERR_UNREACHABLE:
      return "RP_ERR_UNREACHABLE";
    case RP_ERR_JOINT_LIMIT:
      return "RP_ERR_JOINT_LIMIT";
    case RP_ERR_STATE:
      return "RP_ERR_STATE";
    case RP_ERR_NULL:
      return "RP_ERR_NULL";
    case RP_ERR_INTERNAL:
      return "RP_ERR_INTERNAL";
  }
  return "RP_ERR_UNKNOWN";
}

// A Tcl error from a status and its message.
inline int fail(Tcl_Interp* interp, rp_status status, const char* message) {
  const std::string text =
      (message && *message) ? message : std::string("redpost: ") + status_name(status);
  Tcl_SetObjResult(interp, Tcl_NewStringObj(text.c_str(), -1));
  Tcl_SetErrorCode(interp, "REDPOST", status_name(status), static_cast<char*>(nullptr));
  return TCL_ERROR;
}

inline int usage(Tcl_Interp* interp, Tcl_Obj* const objv[], const char* args) {
  Tcl_WrongNumArgs(interp, 1, objv, args);
  return TCL_ERROR;
}

inline int get_session(Tcl_Interp* interp, InterpState* state, Tcl_Obj* obj, rp_session** out) {
  auto it = state->sessions.find(Tcl_GetString(obj));
  if (it == state->sessions.end()) {
    Tcl_SetObjResult(interp, Tcl_ObjPrintf("no redpost session \"%s\"", Tcl_GetString(obj)));
    Tcl_SetErrorCode(interp, "REDPOST", "NO_SESSION", static_cast<char*>(nullptr));
    return TCL_ERROR;
  }
  *out = it->second;
  return TCL_OK;
}

inline int get_reader(Tcl_Interp* interp, InterpState* state, Tcl_Obj* obj, rp_reader** out) {
  auto it = state->readers.find(Tcl_GetString(obj));
  if (it == state->readers.end()) {
    Tcl_SetObjResult(interp, Tcl_ObjPrintf("no redpost reader \"%s\"", Tcl_GetString(obj)));
    Tcl_SetErrorCode(interp, "REDPOST", "NO_READER", static_cast<char*>(nullptr));
    return TCL_ERROR;
  }
  *out = it->second;
  return TCL_OK;
}

// The result of a session call: "" on RP_OK, the session's error otherwise, with the errorCode
// {REDPOST RP_ERR_... LINE}: LINE the CL line (or event number) the error names, 0 for none.
inline int session_result(Tcl_Interp* interp, rp_session* s, rp_status status) {
  if (status == RP_OK) {
    Tcl_ResetResult(interp);
    return TCL_OK;
  }
  fail(interp, status, rp_last_error(s));
  const std::string line = std::to_string(rp_last_error_line(s));
  Tcl_SetErrorCode(interp, "REDPOST", status_name(status), line.c_str(),
                   static_cast<char*>(nullptr));
  return TCL_ERROR;
}

#define STATE static_cast<redpost::tcl::InterpState*>(cd)

// Every session command takes the handle first: parse it and the count of arguments.
#define SESSION_ARGS(n, text)                                          \
  if (objc != (n) + 2)                                                 \
    return redpost::tcl::usage(interp, objv, "session " text);         \
  rp_session* s = nullptr;                                             \
  if (redpost::tcl::get_session(interp, STATE, objv[1], &s) != TCL_OK) \
    return TCL_ERROR;

// The commands of tcl_toolpath.cpp, registered by tcl_package.cpp's init.
struct Command {
  const char* name;
  Tcl_ObjCmdProc* proc;
};
extern const Command kToolpathCommands[];
extern const int kToolpathCommandCount;

}  // namespace redpost::tcl
