// The options of ::redpost::open (tcl_open_options.hpp), as `redpost convert` takes them.
#include "tcl_open_options.hpp"

#include <cmath>
#include <string>

#include "tcl_args.hpp"

#ifndef TCL_SIZE_MAX
typedef int Tcl_Size;  // Tcl 8.6
#endif

namespace redpost::tcl {

namespace {

enum OpenOption {
  o_cell,
  o_krl,
  o_output,
  o_name,
  o_joints,
  o_source,
  o_base,
  o_tool,
  o_apo,
  o_split,
  o_placement,
  o_cl_line_every,
  o_chordal,
  o_tools,
  o_clearance,
  o_rapid_vel,
  o_max_bytes,
  o_plan,
  o_preset,
  o_keyframe_spacing,
  o_lock,
  o_deflection,
  o_cutting,
  o_deflection_tol,
  o_msys,
  o_report,
  o_pipeline,
  o_fit_tol,
  o_fit_ang_tol,
  o_threads,
  o_fixture,
  o_part,
  o_collision_margin,
  o_collision_check
};

// The collision options (docs/collision.md), as convert's --fixture (a list here), --part,
// --collision-margin and --no-collision-check.
int collision_option(Tcl_Interp* interp, int index, Tcl_Obj* v, rp_options& opt,
                     OpenStorage& storage) {
  switch (index) {
    case o_fixture: {
      Tcl_Size n = 0;
      Tcl_Obj** items = nullptr;
      if (Tcl_ListObjGetElements(interp, v, &n, &items) != TCL_OK)
        return TCL_ERROR;
      for (Tcl_Size k = 0; k < n; ++k)
        storage.fixtures.push_back(Tcl_GetString(items[k]));
      opt.fixture_paths = storage.fixtures.empty() ? nullptr : storage.fixtures.data();
      opt.fixture_count = static_cast<int>(storage.fixtures.size());
      return TCL_OK;
    }
    case o_part:
      opt.part_path = *Tcl_GetString(v) ? Tcl_GetString(v) : nullptr;
      return TCL_OK;
    case o_collision_margin:
      return get_double(interp, v, "-collision-margin", &opt.collision_margin_mm);
    case o_collision_check:
      return Tcl_GetBooleanFromObj(interp, v, &opt.collision_check);
    default:
      return TCL_OK;
  }
}

// The options of ::redpost::open added with the deflection model and after it, as `redpost
// convert`'s --predict-deflection, --compensate, --cutting, --deflection-tol, --msys, --report,
// --fit-tol, --fit-ang-tol and --threads (and the pipeline, which convert does not need).
int deflection_option(Tcl_Interp* interp, int index, Tcl_Obj* v, rp_options& opt) {
  switch (index) {
    case o_deflection: {
      static const char* const kModes[] = {"off", "predict", "compensate", nullptr};
      int k = 0;
      if (Tcl_GetIndexFromObj(interp, v, kModes, "-deflection", 0, &k) != TCL_OK)
        return TCL_ERROR;
      opt.deflection = k == 2   ? RP_DEFLECTION_COMPENSATE
                       : k == 1 ? RP_DEFLECTION_PREDICT
                                : RP_DEFLECTION_OFF;
      break;
    }
    case o_cutting:
      opt.cutting_path = *Tcl_GetString(v) ? Tcl_GetString(v) : nullptr;
      break;
    case o_deflection_tol:
      return get_double(interp, v, "-deflection-tol", &opt.deflection_tolerance_mm);
    case o_msys: {
      static const char* const kModes[] = {"ignore", "apply", nullptr};
      int k = 0;
      if (Tcl_GetIndexFromObj(interp, v, kModes, "-msys", 0, &k) != TCL_OK)
        return TCL_ERROR;
      opt.msys = k == 1 ? RP_MSYS_APPLY : RP_MSYS_IGNORE;
      break;
    }
    case o_report:
      opt.report_path = *Tcl_GetString(v) ? Tcl_GetString(v) : nullptr;
      break;
    case o_pipeline:
      return Tcl_GetBooleanFromObj(interp, v, &opt.pipeline);
    case o_fit_tol:
      return get_double(interp, v, "-fit-tol", &opt.fit_tolerance_mm);
    case o_fit_ang_tol:
      return get_double(interp, v, "-fit-ang-tol", &opt.fit_angle_tolerance_deg);
    case o_threads:
      return get_int(interp, v, "-threads", &opt.plan_threads);
    default:
      break;
  }
  return TCL_OK;
}

// One word of -lock: "E<n>" holds external axis n where the first pose puts it, "E<n>=<value>"
// at that value (mm or deg), as `redpost convert --lock` does.
int lock_option(Tcl_Interp* interp, Tcl_Obj* word, rp_options& opt) {
  const std::string text = Tcl_GetString(word);
  const std::size_t eq = text.find('=');
  const std::string axis = text.substr(0, eq);
  if (axis.size() != 2 || (axis[0] != 'E' && axis[0] != 'e') || axis[1] < '1' || axis[1] > '6') {
    Tcl_SetObjResult(interp, Tcl_ObjPrintf("-lock \"%s\": name an external axis E1..E6, e.g. "
                                           "-lock {E1=500 E2}",
                                           text.c_str()));
    Tcl_SetErrorCode(interp, "REDPOST", "USAGE", static_cast<char*>(nullptr));
    return TCL_ERROR;
  }
  const int k = axis[1] - '1';
  opt.lock_mask |= 1u << k;
  if (eq == std::string::npos)
    return TCL_OK;
  Tcl_Obj* value = Tcl_NewStringObj(text.c_str() + eq + 1, -1);
  Tcl_IncrRefCount(value);
  const int rc = get_double(interp, value, "-lock", &opt.lock_value[k]);
  Tcl_DecrRefCount(value);
  if (rc == TCL_OK && !std::isfinite(opt.lock_value[k])) {
    Tcl_SetObjResult(interp, Tcl_ObjPrintf("-lock \"%s\": the value is not a finite number (mm or "
                                           "deg)",
                                           text.c_str()));
    Tcl_SetErrorCode(interp, "REDPOST", "USAGE", static_cast<char*>(nullptr));
    return TCL_ERROR;
  }
  return rc;
}

// -placement {x y z a b c} (mm, deg; empty: none), as convert's --placement.
int placement_option(Tcl_Interp* interp, Tcl_Obj* v, rp_options& opt) {
  Tcl_Size n = 0;
  Tcl_Obj** items = nullptr;
  if (Tcl_ListObjGetElements(interp, v, &n, &items) != TCL_OK)
    return TCL_ERROR;
  if (n == 0)
    return TCL_OK;  // empty: no placement
  if (n != 6) {
    Tcl_SetObjResult(interp, Tcl_ObjPrintf("-placement takes six numbers {x y z a b c}, got \"%s\"",
                                           Tcl_GetString(v)));
    Tcl_SetErrorCode(interp, "REDPOST", "USAGE", static_cast<char*>(nullptr));
    return TCL_ERROR;
  }
  for (int k = 0; k < 6; ++k) {
    if (get_double(interp, items[k], "-placement", &opt.placement[k]) != TCL_OK)
      return TCL_ERROR;
  }
  opt.has_placement = 1;
  return TCL_OK;
}

}  // namespace

const char* const kOpenUsage =
    "-cell CELL.xml -output DIR -name NAME ?-krl SET.xml? ?-joints-csv FILE? ?-source NAME? "
    "?-base EXPR? ?-tool EXPR? ?-placement {x y z a b c}? ?-apo MM? ?-split N? "
    "?-cl-line-every N? ?-chordal-tol MM? ?-tools FILE? ?-clearance Z? ?-rapid-vel M/S? "
    "?-max-bytes N? ?-plan global|local? ?-preset smooth|stiff|fast? ?-keyframe-spacing MM? "
    "?-lock {E1=500 E2 ...}? ?-deflection off|predict|compensate? ?-cutting FILE? "
    "?-deflection-tol MM? ?-msys ignore|apply? ?-report FILE.html? ?-pipeline 0|1? "
    "?-fit-tol MM? ?-fit-ang-tol DEG? ?-threads N? ?-fixture {F.stl ...}? ?-part F.stl? "
    "?-collision-margin MM? ?-collision-check 0|1?";

// The options of ::redpost::open, in the order of kOpenOptions.
const char* const kOpenOptions[] = {"-cell",
                                    "-krl",
                                    "-output",
                                    "-name",
                                    "-joints-csv",
                                    "-source",
                                    "-base",
                                    "-tool",
                                    "-apo",
                                    "-split",
                                    "-placement",
                                    "-cl-line-every",
                                    "-chordal-tol",
                                    "-tools",
                                    "-clearance",
                                    "-rapid-vel",
                                    "-max-bytes",
                                    "-plan",
                                    "-preset",
                                    "-keyframe-spacing",
                                    "-lock",
                                    "-deflection",
                                    "-cutting",
                                    "-deflection-tol",
                                    "-msys",
                                    "-report",
                                    "-pipeline",
                                    "-fit-tol",
                                    "-fit-ang-tol",
                                    "-threads",
                                    "-fixture",
                                    "-part",
                                    "-collision-margin",
                                    "-collision-check",
                                    nullptr};
// One option of ::redpost::open into `opt` (the strings stay owned by the Tcl objects for the
// duration of rp_open).
int open_option(Tcl_Interp* interp, int index, Tcl_Obj* v, rp_options& opt, OpenStorage& storage) {
  if (index >= o_fixture)
    return collision_option(interp, index, v, opt, storage);
  switch (index) {
    case o_cell:
      opt.cell_path = Tcl_GetString(v);
      break;
    case o_krl:
      opt.krl_path = *Tcl_GetString(v) ? Tcl_GetString(v) : nullptr;
      break;
    case o_output:
      opt.output_dir = Tcl_GetString(v);
      break;
    case o_name:
      opt.program_name = Tcl_GetString(v);
      break;
    case o_joints:
      opt.joints_csv_path = *Tcl_GetString(v) ? Tcl_GetString(v) : nullptr;
      break;
    case o_source:
      opt.source_name = Tcl_GetString(v);
      break;
    case o_base:
      opt.base = *Tcl_GetString(v) ? Tcl_GetString(v) : nullptr;
      break;
    case o_tools:
      opt.tools_path = *Tcl_GetString(v) ? Tcl_GetString(v) : nullptr;
      break;
    case o_clearance:
      if (*Tcl_GetString(v)) {  // empty: none
        if (get_double(interp, v, "-clearance", &opt.clearance_z_mm) != TCL_OK)
          return TCL_ERROR;
        opt.has_clearance = 1;
      }
      break;
    case o_rapid_vel:
      if (get_double(interp, v, "-rapid-vel", &opt.rapid_velocity_m_per_s) != TCL_OK)
        return TCL_ERROR;
      break;
    case o_max_bytes: {
      Tcl_WideInt n = 0;
      if (Tcl_GetWideIntFromObj(interp, v, &n) != TCL_OK)
        return TCL_ERROR;
      opt.max_file_bytes = static_cast<long>(n);
      break;
    }
    case o_tool:
      opt.tool = Tcl_GetString(v);
      break;
    case o_plan: {
      static const char* const kPlans[] = {"global", "local", nullptr};
      int k = 0;
      if (Tcl_GetIndexFromObj(interp, v, kPlans, "-plan", 0, &k) != TCL_OK)
        return TCL_ERROR;
      opt.plan = k == 0 ? RP_PLAN_GLOBAL : RP_PLAN_LOCAL;
      break;
    }
    case o_preset: {
      static const char* const kPresets[] = {"smooth", "stiff", "fast", nullptr};
      int k = 0;
      if (Tcl_GetIndexFromObj(interp, v, kPresets, "-preset", 0, &k) != TCL_OK)
        return TCL_ERROR;
      opt.plan_preset = k == 1 ? RP_PLAN_STIFF : k == 2 ? RP_PLAN_FAST : RP_PLAN_SMOOTH;
      break;
    }
    case o_keyframe_spacing:
      if (get_double(interp, v, "-keyframe-spacing", &opt.keyframe_spacing_mm) != TCL_OK)
        return TCL_ERROR;
      break;
    case o_lock: {
      Tcl_Size n = 0;
      Tcl_Obj** items = nullptr;
      if (Tcl_ListObjGetElements(interp, v, &n, &items) != TCL_OK)
        return TCL_ERROR;
      for (Tcl_Size k = 0; k < n; ++k) {
        if (lock_option(interp, items[k], opt) != TCL_OK)
          return TCL_ERROR;
      }
      break;
    }
    case o_apo:
      if (get_double(interp, v, "-apo", &opt.apo_mm) != TCL_OK)
        return TCL_ERROR;
      break;
    case o_split:
      if (get_int(interp, v, "-split", &opt.motions_per_file) != TCL_OK)
        return TCL_ERROR;
      break;
    case o_cl_line_every:
      if (get_int(interp, v, "-cl-line-every", &opt.cl_line_every) != TCL_OK)
        return TCL_ERROR;
      break;
    case o_chordal:
      if (get_double(interp, v, "-chordal-tol", &opt.chordal_tolerance_mm) != TCL_OK)
        return TCL_ERROR;
      break;
    case o_placement:
      return placement_option(interp, v, opt);
    default:
      return deflection_option(interp, index, v, opt);
  }
  return TCL_OK;
}

}  // namespace redpost::tcl
