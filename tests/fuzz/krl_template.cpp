// Fuzz target: the KRL template loader (krl/template.hpp). A template set it accepts then writes
// a small split program (every statement kind once) into a scratch directory, so that the
// writer's placeholder substitution sees the fuzzed templates too.
#include <cmath>

#include "fuzz_support.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/krl/writer.hpp"

namespace {

redpost::KrlMotion motion(redpost::KrlMotionKind kind, double x_mm, int cl_line) {
  redpost::KrlMotion m;
  m.kind = kind;
  const double axes_deg[8] = {0, -90, 90, 0, 90, 0, 500, 10};  // A1..A6, E1 (mm), E2 (deg)
  for (int i = 0; i < 6; ++i)
    m.axes.arm(i + 1) = axes_deg[i];
  m.axes.external(1) = axes_deg[6];
  m.axes.external(2) = axes_deg[7];
  m.T_base_tcp = redpost::Isometry::Identity();
  m.T_base_tcp.translation() << x_mm, 20.0, 30.0;
  m.status_turn = {2, 10};
  m.cl_line = cl_line;
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return redpost::fuzz::run_one([&] {
    const redpost::KrlTemplateSet templates =
        redpost::parse_krl_templates(redpost::fuzz::as_text(data, size), "fuzz.xml");
    redpost::KrlProgramInfo info;
    info.name = "FUZZ";
    info.output_dir = redpost::fuzz::fresh_scratch_dir().string();
    info.motions_per_file = 2;
    info.cl_line_every = 1;
    info.header_comment = "fuzz";
    redpost::KrlWriter writer(templates, info);
    writer.comment("start");
    redpost::KrlToolChange change;
    change.number = 2;
    change.name = "T2";
    change.tool_data = 2;
    change.tool = "TOOL_DATA[2]";
    writer.tool_change(change);
    writer.dwell(0.5);
    writer.spindle(8000, true);
    writer.coolant(true, "FLOOD");
    writer.motion(motion(redpost::KrlMotionKind::ptp_axes, 0.0, 1));
    writer.motion(motion(redpost::KrlMotionKind::rapid, 1.0, 2));
    writer.velocity(0.02);
    writer.motion(motion(redpost::KrlMotionKind::lin, 2.0, 3));
    writer.literal("WAIT SEC 0");
    writer.motion(motion(redpost::KrlMotionKind::lin, 3.0, 4));
    writer.coolant(false, "");
    writer.spindle(0, true);
    writer.finish();
  });
}
