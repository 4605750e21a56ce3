// The options of ::redpost::open (tcl_package.cpp) into rp_options: their names, the usage
// message, and one option's value read into the options.
//
// Internal to the plugin; not installed.
#pragma once

#include <tcl.h>

#include "redpost.h"

namespace redpost::tcl {

extern const char* const kOpenUsage;
// The option names, NULL-terminated, in the order open_option's index takes them.
extern const char* const kOpenOptions[];

// Option number `index` of kOpenOptions with the value v into `opt` (the strings stay owned by
// the Tcl objects for the duration of rp_open). TCL_ERROR with a message in the interpreter.
int open_option(Tcl_Interp* interp, int index, Tcl_Obj* v, rp_options& opt);

}  // namespace redpost::tcl
