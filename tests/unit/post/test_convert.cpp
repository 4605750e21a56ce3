// The whole pipeline on the project's examples: CL file -> reader -> session -> KRL and joints
// CSV. Checked against independent data: the CL targets in the input file, forward kinematics
// of the logged joints, and the KRL read back with a small reader written here.
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "catch_compat.hpp"
#include "redpost/cl/reader.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/post/session.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace redpost;
namespace fs = std::filesystem;

namespace {

struct Converted {
  fs::path dir;
  PostSummary summary;
};

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("redpost_test_convert_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  test::remove_at_exit(dir);
  return dir;
}

Converted convert(const std::string& example, const std::string& cell_name,
                  const std::string& templates = "krc4_lin", int split = 0) {
  const Cell cell = test::shipped_cell(cell_name);
  const KrlTemplateSet krl =
      load_krl_templates(test::source_path("definitions/krl/" + templates + ".xml"));
  Converted out;
  out.dir = fresh_dir(example + "_" + templates);
  PostOptions o;
  o.program.name = "PROG";
  o.program.output_dir = out.dir.string();
  o.program.motions_per_file = split;
  o.source_name = test::source_path("examples/cl/" + example);
  o.joints_csv_path = (out.dir / "joints.csv").string();
  std::ifstream in = open_text_stream(o.source_name);
  ClReader reader(in, o.source_name);
  PostSession session(cell, krl, o);
  ClEvent e;
  while (reader.next(e))
    session.handle(e);
  out.summary = session.finish();
  return out;
}

// CL targets by line: the GOTOs of the input (position and the tool axis in force).
std::map<int, std::pair<Eigen::Vector3d, Eigen::Vector3d>> goto_targets(const std::string& path) {
  std::map<int, std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
  std::ifstream in(path);
  std::string line;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.rfind("GOTO/", 0) != 0)
      continue;
    std::string values = line.substr(5);
    for (char& c : values)
      c = c == ',' ? ' ' : c;
    std::istringstream s(values);
    double v[6];
    int k = 0;
    while (k < 6 && s >> v[k])
      ++k;
    if (k == 6)
      axis = Eigen::Vector3d(v[3], v[4], v[5]).normalized();
    out[n] = {Eigen::Vector3d(v[0], v[1], v[2]), axis};
  }
  return out;
}

struct CsvRow {
  int cl_line = 0;
  JointVector q;
  std::vector<double> axes;
};

std::vector<CsvRow> read_csv(const fs::path& path, int n) {
  std::vector<CsvRow> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    for (char& c : line)
      c = c == ',' ? ' ' : c;
    std::istringstream s(line);
    CsvRow r;
    int pose = 0;
    double time_s = 0.0;
    s >> pose >> r.cl_line >> time_s;
    r.q.resize(n);
    for (int i = 0; i < n; ++i)
      s >> r.q[i];
    double a;
    while (s >> a)
      r.axes.push_back(a);
    rows.push_back(r);
  }
  return rows;
}

// Motions of a .src: the keyword and every "NAME value" pair inside its braces.
struct KrlMotionLine {
  std::string keyword;
  std::map<std::string, double> values;
};

std::vector<KrlMotionLine> read_motions(const fs::path& src) {
  static const std::regex motion(R"(^\s*(PTP|LIN|SLIN|SPTP)\s*\{([^}]*)\})");
  static const std::regex pair(R"(([A-Z][A-Z0-9]*)\s+(-?[0-9]+(?:\.[0-9]+)?))");
  std::vector<KrlMotionLine> out;
  std::ifstream in(src);
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, motion))
      continue;
    KrlMotionLine k;
    k.keyword = m[1];
    const std::string body = m[2];
    for (auto it = std::sregex_iterator(body.begin(), body.end(), pair);
         it != std::sregex_iterator(); ++it) {
      k.values[(*it)[1]] = std::stod((*it)[2]);
    }
    out.push_back(k);
  }
  return out;
}

// tool_length_mm: the length of the example's tool (its TLDATA or CUTTER), whose TCP the program
// is solved for (docs/tools.md); 0: the cell's own TCP.
void check_example(const std::string& example, const std::string& templates,
                   double tool_length_mm = 0.0) {
  const Cell shipped = test::shipped_cell("andres2011_kr15_track_table");
  const Cell cell = tool_length_mm > 0.0 ? cell_for_tool(shipped, tool_length_mm) : shipped;
  const Converted c = convert(example, "andres2011_kr15_track_table", templates);
  const auto targets = goto_targets(test::source_path("examples/cl/" + example));
  const auto rows = read_csv(c.dir / "joints.csv", cell.size());
  REQUIRE(static_cast<long>(rows.size()) == c.summary.motions);

  // 1. Forward kinematics of every logged posture meets its CL target where the motion ends a
  //    GOTO (arc and NURBS pieces end on their own intermediate points).
  int checked = 0;
  for (size_t k = 0; k < rows.size(); ++k) {
    REQUIRE(within_limits(cell, rows[k].q, 1e-9));
    const auto t = targets.find(rows[k].cl_line);
    const bool last_of_line = k + 1 == rows.size() || rows[k + 1].cl_line != rows[k].cl_line;
    if (t == targets.end() || !last_of_line)
      continue;
    const Isometry T = tcp_pose(cell, rows[k].q);
    INFO(example << " CL line " << rows[k].cl_line);
    CHECK((T.translation() - t->second.first).norm() < 2e-4);  // 1e-4 + CSV rounding
    CHECK(T.linear().col(2).dot(t->second.second) > std::cos(1e-6));
    ++checked;
  }
  CHECK(checked > 10);

  // 2. The KRL, read back, says the same: E6POS of LINs equals the physical TCP (virtual joint at
  //    0), and E1/E2 and A1..A6 equal the logged axes.
  const auto motions = read_motions(c.dir / "PROG.src");
  REQUIRE(motions.size() == rows.size());
  CHECK(motions.front().keyword == "PTP");
  CHECK(motions.front().values.count("A1") == 1);
  for (size_t k = 0; k < motions.size(); ++k) {
    const KrlMotionLine& m = motions[k];
    const AxisValues axes = to_controller_axes(cell, rows[k].q);
    if (m.values.count("E1"))
      CHECK(m.values.at("E1") == Approx(axes.external(1)).margin(6e-4));
    if (m.values.count("E2"))
      CHECK(m.values.at("E2") == Approx(axes.external(2)).margin(6e-4));
    if (m.values.count("A1")) {
      for (int a = 1; a <= 6; ++a) {
        CHECK(m.values.at("A" + std::to_string(a)) == Approx(axes.arm(a)).margin(6e-4));
      }
    }
    if (m.keyword == "LIN" || m.keyword == "SLIN") {
      JointVector q = rows[k].q;
      q[8] = 0.0;
      const Isometry T = tcp_pose(cell, q);
      CHECK(m.values.at("X") == Approx(T.translation().x()).margin(6e-4));
      CHECK(m.values.at("Y") == Approx(T.translation().y()).margin(6e-4));
      CHECK(m.values.at("Z") == Approx(T.translation().z()).margin(6e-4));
      const Eigen::Matrix3d R =
          rotation_from_abc({m.values.at("A"), m.values.at("B"), m.values.at("C")});
      CHECK(Eigen::AngleAxisd(R.transpose() * T.linear()).angle() < 1e-5);
    }
  }
}

}  // namespace

TEST_CASE("convert: pocket with arcs, FK of the joints and the KRL read back meet the CL") {
  check_example("pocket_arcs.apt", "krc4_lin");
}

TEST_CASE("convert: 5-axis surface pass (NX CLSF)") {
  check_example("surface_5axis.cls", "krc4_lin", 75.0);
}

TEST_CASE("convert: a 2 m pass moves the track and the table, E1 and E2 follow") {
  check_example("long_pass.apt", "krc4_lin");
  const Converted c = convert("long_pass.apt", "andres2011_kr15_track_table");
  const auto& track = c.summary.joints[1];
  INFO("track range " << track.lowest << " .. " << track.highest);
  CHECK(track.highest - track.lowest > 500.0);
}

TEST_CASE("convert: byte-identical output for identical input, and under a German locale") {
  const Converted a = convert("pocket_arcs.apt", "andres2011_kr15_track_table");
  const std::string first = read_text_file((a.dir / "PROG.src").string());
  const std::string first_dat = read_text_file((a.dir / "PROG.dat").string());
  const char* previous = std::setlocale(LC_ALL, nullptr);
  const std::string saved = previous ? previous : "C";
  if (std::setlocale(LC_ALL, "de_DE.UTF-8") == nullptr) {
    WARN("de_DE.UTF-8 is not installed (scripts/setup.sh generates it): locale part skipped");
  } else {
    std::locale::global(std::locale("de_DE.UTF-8"));
  }
  const Converted b = convert("pocket_arcs.apt", "andres2011_kr15_track_table");
  std::locale::global(std::locale::classic());
  std::setlocale(LC_ALL, saved.c_str());
  CHECK(read_text_file((b.dir / "PROG.src").string()) == first);
  CHECK(read_text_file((b.dir / "PROG.dat").string()) == first_dat);
}

TEST_CASE("convert: an unreachable path fails with the CL line and leaves no program") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet krl = load_krl_templates(test::source_path("definitions/krl/krc4_lin.xml"));
  const fs::path dir = fresh_dir("unreachable");
  PostOptions o;
  o.program.name = "FAR";
  o.program.output_dir = dir.string();
  o.source_name = "far.apt";
  std::istringstream in(
      "UNITS/MM\nRAPID\nGOTO/-100,-450,100\nFEDRAT/MMPM,1000\nGOTO/-100,-450,60\n"
      "GOTO/-100,-450,3000\nFINI\n");
  try {
    ClReader reader(in, "far.apt");
    PostSession session(cell, krl, o);
    ClEvent e;
    while (reader.next(e))
      session.handle(e);
    session.finish();
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(e.where().file == "far.apt");
    CHECK(e.where().line == 6);
    // Straight up from the table: the arm stretches until A5 would leave its range, or the target
    // is simply out of reach, depending on the posture; either is reported at the CL line.
    const std::string what = e.what();
    CHECK((e.code() == ErrorCode::unreachable || e.code() == ErrorCode::joint_limit));
    CHECK((what.find("cannot be reached") != std::string::npos ||
           what.find("(A5) would have to leave its limits [-130.000 deg, 130.000 deg]") !=
               std::string::npos));
  }
  for (const auto& f : fs::directory_iterator(dir))
    FAIL("left behind: " << f.path());
}
