// The session's pipeline (PostOptions::plan_threads >= 2, post/dispatch_stage.hpp): the next
// window planned while the calls the last one released are tracked and written on a thread of
// the session's own. Checked against the serial session: the same files byte for byte, the same
// summary, the same error, on the examples, across tool changes, and where every window falls
// back to tracking pose by pose (each next window then waits for the tracker).
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "catch_compat.hpp"
#include "redpost/cl/reader.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/post/session.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace redpost;
namespace fs = std::filesystem;

namespace {

struct Run {
  std::string files;  // every file written, name and bytes, in name order
  PostSummary summary;
  std::string error;  // what was thrown (empty: none)
  bool left_files = false;
};

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("redpost_test_pipeline_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  test::remove_at_exit(dir);
  return dir;
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Converts `source` (a CL file) on the reference cell with the whole-path plan.
Run convert(const std::string& source, int threads, double max_arm_step_deg = 30.0,
            MotionObserver observer = {}) {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet krl = load_krl_templates(test::source_path("definitions/krl/krc4_lin.xml"));
  const fs::path dir = fresh_dir(fs::path(source).stem().string() + "_" + std::to_string(threads));
  PostOptions o;
  o.program.name = "PROG";
  o.program.output_dir = dir.string();
  o.source_name = source;
  o.joints_csv_path = (dir / "joints.csv").string();
  o.plan = RedundancyPlan::global;
  o.plan_threads = threads;
  o.plan_settings.max_arm_step_deg = max_arm_step_deg;
  o.on_motion = std::move(observer);
  Run out;
  try {
    std::ifstream in = open_text_stream(source);
    ClReaderOptions ro;
    ro.toolpath_events = true;  // expanded by the session's own expander, as convert does
    ClReader reader(in, source, ro);
    PostSession session(cell, krl, o);
    ClEvent e;
    while (reader.next(e))
      session.handle(e);
    out.summary = session.finish();
  } catch (const Error& e) {
    out.error = e.what();
  }
  std::vector<fs::path> files;
  for (const fs::directory_entry& f : fs::directory_iterator(dir))
    files.push_back(f.path());
  std::sort(files.begin(), files.end());
  out.left_files = !out.error.empty() && !files.empty();
  for (const fs::path& f : files)
    out.files += f.filename().string() + "\n" + read_all(f);
  return out;
}

void check_same(const Run& a, const Run& b) {
  CHECK(a.error == b.error);
  CHECK(a.files == b.files);
  CHECK(a.summary.motions == b.summary.motions);
  CHECK(a.summary.poses == b.summary.poses);
  CHECK(a.summary.plan_windows == b.summary.plan_windows);
  CHECK(a.summary.plan_ik_evaluations == b.summary.plan_ik_evaluations);
  CHECK(a.summary.plan_fallback_windows == b.summary.plan_fallback_windows);
  CHECK(a.summary.warnings == b.summary.warnings);
}

// Writes `text` to a CL file of the test's own.
std::string cl_file(const std::string& name, const std::string& text) {
  const fs::path p = fresh_dir("cl_" + name) / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

// A zigzag of `lines` passes of `points` points 0.5 mm apart, with tool `tool` (LOADTL).
std::string zigzag(int tool, int lines, int points, double y0) {
  std::ostringstream s;
  s << "LOADTL/" << tool << "\nSPINDL/9000,RPM,CLW\nRAPID\nGOTO/-100," << y0
    << ",100,0,0.2,0.9797959\n"
    << "FEDRAT/MMPM,3000\n";
  for (int l = 0; l < lines; ++l) {
    for (int k = 0; k < points; ++k) {
      const int i = (l % 2 == 0) ? k : points - 1 - k;
      s << "GOTO/" << (-100.0 + 0.5 * i) << "," << (y0 - 3.0 * l) << ",60,0,0.2,0.9797959\n";
    }
  }
  return s.str();
}

}  // namespace

TEST_CASE("pipeline: the examples, the same files and summary with 1, 2 and 3 threads") {
  for (const char* example : {"pocket_arcs.apt", "surface_5axis.cls", "long_pass.apt"}) {
    const std::string source = test::source_path(std::string("examples/cl/") + example);
    const Run one = convert(source, 1);
    REQUIRE(one.error.empty());
    for (int threads : {2, 3}) {
      INFO(example << ", " << threads << " threads");
      check_same(one, convert(source, threads));
    }
  }
}

TEST_CASE("pipeline: tool changes wait for the new tool's cell, the same program") {
  const std::string source =
      cl_file("tools.apt", "UNITS/MM\nMULTAX/ON\n" + zigzag(1, 16, 400, -450) +
                               zigzag(2, 10, 400, -480) + zigzag(1, 12, 400, -500) + "FINI\n");
  const Run one = convert(source, 1);
  REQUIRE(one.error.empty());
  CHECK(one.summary.plan_windows >= 6);
  check_same(one, convert(source, 2));
}

TEST_CASE("pipeline: windows that fall back to pose by pose wait for the tracker") {
  // No arm step allowed between keyframes: no window has a sequence on the lattice, every
  // stretch is tracked pose by pose, and each next window starts from the tracker's posture.
  const std::string source = test::source_path("examples/cl/long_pass.apt");
  const Run one = convert(source, 1, 1e-6);
  REQUIRE(one.error.empty());
  CHECK(one.summary.plan_fallback_windows > 1);
  check_same(one, convert(source, 2, 1e-6));
}

TEST_CASE("pipeline: the reading's warnings among the tracking's, in the serial order") {
  // A PPRINT every 500 lines (the expander warns while it reads) and two tool changes without a
  // tool table (the tracking side warns when it changes the tool).
  std::string text = "UNITS/MM\nMULTAX/ON\n" + zigzag(1, 14, 400, -450) + zigzag(2, 12, 400, -480) +
                     zigzag(3, 6, 400, -500);
  std::istringstream lines(text);
  std::ostringstream out;
  std::string l;
  for (int n = 1; std::getline(lines, l); ++n) {
    if (n % 500 == 0)
      out << "PPRINT/ NOTE " << n << "\n";
    out << l << "\n";
  }
  const std::string source = cl_file("notes.apt", out.str());
  const Run one = convert(source, 1);
  REQUIRE(one.error.empty());
  int notes = 0, tools = 0;
  for (const std::string& w : one.summary.warnings) {
    notes += w.find("PPRINT/ text") != std::string::npos ? 1 : 0;
    tools += w.find("no tool table") != std::string::npos ? 1 : 0;
  }
  CHECK(notes == 20);  // the expander's cap
  CHECK(tools >= 2);
  for (int threads : {2, 3}) {
    INFO(threads << " threads");
    check_same(one, convert(source, threads));
  }
}

TEST_CASE("pipeline: the error of a call the tracking thread failed comes first, nothing left") {
  // The observer fails the third motion, slowly: the serial session fails there, when the
  // first window is released (about CL line 4700). The pipeline's reading goes on meanwhile and
  // meets a feed the controller cannot take at line 5200: the tracking thread's error is still
  // the one told, as without the pipeline.
  std::string text = "UNITS/MM\nMULTAX/ON\n" + zigzag(1, 30, 400, -450);
  std::istringstream lines(text);
  std::ostringstream bad;
  std::string l;
  for (int n = 1; std::getline(lines, l); ++n) {
    if (n == 5200)
      bad << "FEDRAT/MMPM,500000\n";
    bad << l << "\n";
  }
  const std::string source = cl_file("bad.apt", bad.str());
  const auto failing = [] {
    return [count = 0](const MotionSample&) mutable {
      if (++count == 3) {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        throw Error(ErrorCode::bad_input, "the observer stops at the third motion");
      }
    };
  };
  const Run one = convert(source, 1, 30.0, failing());
  INFO(one.error);
  CHECK(one.error.find("the observer stops at the third motion") != std::string::npos);
  CHECK_FALSE(one.left_files);
  for (int threads : {2, 3}) {
    const Run many = convert(source, threads, 30.0, failing());
    CHECK(many.error == one.error);
    CHECK_FALSE(many.left_files);
  }
  // Without the observer, the feed is the error, whatever the threads.
  const Run feed = convert(source, 2);
  CHECK(feed.error.find("bad.apt:5200: feed 500000 mm/min") != std::string::npos);
}
