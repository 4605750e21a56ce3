// The reading-and-writing floor of `redpost convert` (issue 32; docs/performance.md, "The
// pipeline"): a CL file read as convert reads it (ClReader, the session's ClExpander and point
// reduction), and every motion that gives formatted and written through the same KrlWriter and
// template set, with no kinematics at all: each motion at the cell's home posture (A1..A6,
// E1..E6) and its TCP frame at the CL point with the CL tool axis. No plan, no tracking, no time
// model: what convert costs beyond this is theirs. Each move the reduction gives is one motion
// (fewer than convert writes, which writes a move whose straight line it cannot prove in the
// steps it tracked it in); with `steps`, every move in those steps (PostOptions::max_step_mm,
// max_step_axis_deg): more than convert writes. For
// tests/bench/convert_bench.sh only: the program it writes is not one to run on a robot (its axis
// values are all the home posture's).
//
// Usage: redpost_bench_read_write CL_FILE CELL.xml TEMPLATE_SET.xml OUT_DIR NAME [steps]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "redpost/cl/expander.hpp"
#include "redpost/cl/point_reduction.hpp"
#include "redpost/cl/reader.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/krl/writer.hpp"
#include "redpost/post/session.hpp"

namespace {

using namespace redpost;

// The TCP frame of a CL point: z along the tool axis (any x about it).
Isometry cl_frame(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis) {
  Isometry T = Isometry::Identity();
  T.linear() =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis.normalized()).matrix();
  T.translation() = p_mm;
  return T;
}

struct Floor {
  const AxisValues home_axes;
  KrlWriter& writer;
  const PostOptions& o;
  bool in_steps = false;
  bool rapid_next = false;
  bool started = false;
  Eigen::Vector3d p_last = Eigen::Vector3d::Zero(), z_last = Eigen::Vector3d::UnitZ();
  long motions = 0;

  void write(KrlMotionKind kind, const Eigen::Vector3d& p_mm, const Eigen::Vector3d& z, int line) {
    KrlMotion m;
    m.kind = kind;
    m.axes = home_axes;
    m.T_base_tcp = cl_frame(p_mm, z);
    m.cl_line = line;
    writer.motion(m);
    ++motions;
  }

  // The move in the session's steps (motion.cpp, track_line).
  void move(const ClEvent& e) {
    const KrlMotionKind kind = (rapid_next || e.rapid) ? KrlMotionKind::rapid : KrlMotionKind::lin;
    const Eigen::Vector3d z = e.tool_axis.normalized();
    const double length = (e.p_mm - p_last).norm();
    const double turn_deg =
        std::acos(std::clamp(z.dot(z_last), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
    const int steps =
        started && in_steps
            ? std::max(1, static_cast<int>(std::ceil(
                              std::max(length / o.max_step_mm, turn_deg / o.max_step_axis_deg))))
            : 1;
    for (int s = 1; s <= steps; ++s) {
      const double t = static_cast<double>(s) / steps;
      write(kind, (1.0 - t) * p_last + t * e.p_mm, ((1.0 - t) * z_last + t * z).normalized(),
            e.line);
    }
    started = true;
    rapid_next = false;
    p_last = e.p_mm;
    z_last = z;
  }

  void event(const ClEvent& e) {
    switch (e.kind) {
      case ClEventKind::feed:
        writer.velocity(e.value / 60000.0);
        break;
      case ClEventKind::rapid:
        rapid_next = true;
        break;
      case ClEventKind::move:
      case ClEventKind::arc:  // to its end: the floor has no arcs of its own
        move(e);
        break;
      case ClEventKind::tool_change: {
        KrlToolChange c;
        c.number = e.tool_number;
        c.name = e.text;
        c.tool_data = std::max(1, e.tool_number);
        c.tool = "TOOL_DATA[" + std::to_string(c.tool_data) + "]";
        writer.tool_change(c);
        break;
      }
      case ClEventKind::spindle:
        writer.spindle(e.value, e.direction != SpindleDirection::counter_clockwise);
        break;
      case ClEventKind::comment:
        writer.comment(e.text);
        break;
      default:
        break;
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6 || argc > 7 || (argc == 7 && std::string(argv[6]) != "steps")) {
    std::fprintf(stderr,
                 "usage: redpost_bench_read_write CL_FILE CELL.xml TEMPLATE_SET.xml "
                 "OUT_DIR NAME [steps]\n");
    return 2;
  }
  try {
    const Cell cell = load_cell(argv[2]);
    const KrlTemplateSet templates = load_krl_templates(argv[3]);
    PostOptions o;  // convert's defaults: the same point reduction
    o.reduction.tolerance_mm = 0.01;
    o.reduction.axis_tolerance_deg = 0.1;
    KrlProgramInfo info;
    info.name = argv[5];
    info.output_dir = argv[4];
    KrlWriter writer(templates, info);
    ClExpanderOptions eo;
    eo.chordal_tolerance_mm = o.chordal_tolerance_mm;
    eo.point_match_tolerance_mm = o.arc_point_tolerance_mm;
    ClExpander front(argv[1], eo, [](const std::string&) {});
    PointReducer reducer(session_reduction(o, writer, templates));
    std::ifstream in(argv[1], std::ios::binary);
    if (!in)
      throw Error(ErrorCode::io, std::string("cannot open ") + argv[1]);
    ClReader reader(in, argv[1]);
    Floor floor{to_controller_axes(cell, cell.home()), writer, o, argc == 7};
    ClEvent e, x, r;
    while (reader.next(e)) {
      front.push(e);
      while (front.next(x)) {
        reducer.push(x);
        while (reducer.next(r))
          floor.event(r);
      }
    }
    reducer.finish();
    while (reducer.next(r))
      floor.event(r);
    writer.finish();
    std::printf("%ld motions\n", floor.motions);
  } catch (const Error& err) {
    std::fprintf(stderr, "%s\n", err.what());
    return 1;
  }
  return 0;
}
