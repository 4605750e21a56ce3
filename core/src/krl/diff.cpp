// Comparing two KRL programs motion by motion (docs/krl-diff.md): the quantities' names and
// units, and programs already read compared as streams (krl/diff_stream.hpp). Files and
// directories: diff_folders.cpp; the reports: diff_report.cpp.
#include "redpost/krl/diff.hpp"

#include "krl/diff_source.hpp"
#include "krl/diff_stream.hpp"

namespace redpost {

const char* krl_quantity_name(KrlQuantity q) {
  static const char* const names[kKrlQuantityCount] = {"position",     "orientation",
                                                       "aux_position", "A1",
                                                       "A2",           "A3",
                                                       "A4",           "A5",
                                                       "A6",           "E1",
                                                       "E2",           "E3",
                                                       "E4",           "E5",
                                                       "E6",           "status",
                                                       "turn",         "keyword",
                                                       "target_kind",  "vel_cp",
                                                       "apo_cdis",     "ptp_velocity",
                                                       "tool",         "base",
                                                       "path",         "path_orientation"};
  return names[static_cast<int>(q)];
}

bool krl_quantity_is_summarised(KrlQuantity q) {
  switch (q) {
    case KrlQuantity::keyword:
    case KrlQuantity::target_kind:
    case KrlQuantity::vel_cp:
    case KrlQuantity::apo_cdis:
    case KrlQuantity::ptp_velocity:
    case KrlQuantity::tool:
    case KrlQuantity::base:
    case KrlQuantity::path:
    case KrlQuantity::path_orientation:
      return true;
    default:
      return false;
  }
}

const char* krl_quantity_unit(KrlQuantity q) {
  switch (q) {
    case KrlQuantity::position:
    case KrlQuantity::aux_position:
    case KrlQuantity::apo_cdis:
    case KrlQuantity::path:
      return "mm";
    case KrlQuantity::orientation:
    case KrlQuantity::path_orientation:
      return "deg";
    case KrlQuantity::vel_cp:
      return "m/s";
    case KrlQuantity::ptp_velocity:
      return "%";
    case KrlQuantity::status:
    case KrlQuantity::turn:
    case KrlQuantity::keyword:
    case KrlQuantity::target_kind:
    case KrlQuantity::tool:
    case KrlQuantity::base:
      return "";
    default:
      return "axis";  // deg for rotary axes, mm for linear ones
  }
}

KrlDiffResult diff_krl_programs(const KrlProgram& a, const KrlProgram& b,
                                const KrlDiffOptions& options) {
  krl::ProgramPoseSource sa(a), sb(b);
  return krl::diff_pose_streams(sa, sb, options);
}

}  // namespace redpost
