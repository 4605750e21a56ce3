// The options of ::redpost::open (tcl_package.cpp) into rp_options: their names, the usage
// message, and one option's value read into the options.
//
// Internal to the plugin; not installed.
#pragma once

#include <tcl.h>

#include <vector>

#include "redpost.h"

namespace redpost::tcl {

extern const char* const kOpenUsage;
// The option names, NULL-terminated, in the order open_option's index takes them.
extern const char* const kOpenOptions[];

// What rp_options points to beyond the Tcl objects' own strings: the array of fixture paths.
struct OpenStorage {
  std::vector<const char*> fixtures;
};

// Option number `index` of kOpenOptions with the value v into `opt` (the strings stay owned by
// the Tcl objects for the duration of rp_open; `storage` must outlive it too). TCL_ERROR with a
// message in the interpreter.
int open_option(Tcl_Interp* interp, int index, Tcl_Obj* v, rp_options& opt, OpenStorage& storage);

}  // namespace redpost::tcl
