// The readings file of the calibration (issue 7): round trips and bad rows with their lines.
#include <string>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/calibration/identification.hpp"
#include "redpost/calibration/parameters.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/calibration/readings_csv.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

const Cell& andres() {
  static const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  return cell;
}

// The paper's plan with readings simulated from a cell whose link 1 d is off by 0.4 mm.
const std::vector<CalibrationPoint>& simulated_plan() {
  static const std::vector<CalibrationPoint> pts = [] {
    std::vector<CalibrationPoint> p = plan_calibration(andres());
    const std::vector<CalibrationParameter> d1{parse_calibration_parameter("link1.d", andres())};
    Eigen::VectorXd v = parameter_values(andres(), d1);
    v[0] += 0.4;
    simulate_readings(apply_parameters(andres(), d1, v), p, 0.035, 7);
    return p;
  }();
  return pts;
}

// Expects parse_readings_csv to fail with bad_input at `line` with `what` in the message.
void expect_bad(const std::string& text, int line, const std::string& what) {
  INFO(text);
  try {
    parse_readings_csv(text, "r.csv", andres());
    FAIL("no error for a bad readings file");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(e.where().file == "r.csv");
    CHECK(e.where().line == line);
    INFO(e.message());
    CHECK(e.message().find(what) != std::string::npos);
  }
}

const std::string kPoseHeader = "plane,distance,x,y,z,a,b,c,q1,q2\n";
const std::string kGoodPoseRow = "z,0.25,-200,-200,0,0,0,0,0,700\n";

std::string joints_header() {
  std::string h = "plane,distance";
  for (int i = 1; i <= andres().size(); ++i)
    h += ",q" + std::to_string(i);
  return h + "\n";
}

}  // namespace

TEST_CASE("calibration csv: the joints form round-trips exactly") {
  const auto& pts = simulated_plan();
  ReadingsWriteOptions w;
  w.form = ReadingsForm::joints;
  const std::string text = format_readings_csv(andres(), pts, w);
  const auto back = parse_readings_csv(text, "joints.csv", andres());
  REQUIRE(back.size() == pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    CHECK(back[i].plane == pts[i].plane);
    CHECK(back[i].reading_mm == pts[i].reading_mm);
    CHECK(back[i].q == pts[i].q);
  }
}

TEST_CASE("calibration csv: a UTF-8 byte order mark before the header is not part of it") {
  const auto& pts = simulated_plan();
  ReadingsWriteOptions w;
  w.form = ReadingsForm::joints;
  const std::string text = format_readings_csv(andres(), pts, w);
  const auto plain = parse_readings_csv(text, "joints.csv", andres());
  const auto bom = parse_readings_csv("\xEF\xBB\xBF" + text, "joints.csv", andres());
  REQUIRE(bom.size() == plain.size());
  for (size_t i = 0; i < bom.size(); ++i)
    CHECK(bom[i].q == plain[i].q);
  // Only at the start of the file: elsewhere the bytes are data, and refused as such.
  CHECK_THROWS_AS(parse_readings_csv(text + "\xEF\xBB\xBF" + "1,2\n", "joints.csv", andres()),
                  Error);
}

TEST_CASE("calibration csv: the commanded-pose form round-trips through the nominal model") {
  const auto& pts = simulated_plan();
  const std::string text = format_readings_csv(andres(), pts);
  CHECK(text.find("plane,distance,x,y,z,a,b,c,q1,q2\n") != std::string::npos);
  const auto back = parse_readings_csv(text, "pose.csv", andres());
  REQUIRE(back.size() == pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    CHECK(back[i].plane == pts[i].plane);
    CHECK(back[i].reading_mm == pts[i].reading_mm);
    CHECK(back[i].configuration == pts[i].configuration);
    CHECK((back[i].q - pts[i].q).cwiseAbs().maxCoeff() < 1e-9);
    CHECK(back[i].T_B_commanded.isApprox(pts[i].T_B_commanded, 1e-12));
  }
  // Calibrating from the file gives what calibrating from the points gives.
  const auto params = default_calibration_parameters();
  const CalibrationResult a = calibrate(andres(), params, pts);
  const CalibrationResult b = calibrate(andres(), params, back);
  CHECK((a.values - b.values).cwiseAbs().maxCoeff() < 1e-6);
}

TEST_CASE("calibration csv: the template has blank distances, which read back as an error") {
  ReadingsWriteOptions w;
  w.blank_distances = true;
  const std::string text = format_readings_csv(andres(), plan_calibration(andres()), w);
  CHECK(text.rfind("# ", 0) == 0);  // a comment line, then the header on line 2
  CHECK(text.find("\nx,,0,-200,150,0,-90,0,0,700\n") != std::string::npos);
  expect_bad(text, 3, "column 'distance' is empty");
}

TEST_CASE("calibration csv: bad headers are reported with their line") {
  expect_bad("", 0, "no header row");
  expect_bad("# only a comment\n\n", 2, "no header row");
  expect_bad(kPoseHeader, 1, "no readings");
  expect_bad("# comment\nplane,distance,x,y,z,a,b,c,q1,q2,w\n" + kGoodPoseRow, 2,
             "unknown column 'w'");
  expect_bad("plane,distance,x,y,z,a,b,c,q1,q1\n", 1, "'q1' appears twice");
  expect_bad("plane,distance,x,y,z,a,b,q1,q2\n", 1, "missing c");
  expect_bad("plane,distance,x,y,z,a,b,c\n", 1, "external joints");
  expect_bad("plane,distance,x,y,z,a,b,c,q1,q10\n", 1, "the cell has 9 joints");
  expect_bad("plane,distance,q1,q2,q3\n", 1, "missing q4, q5, q6, q7, q8, q9");
  expect_bad("distance,x,y,z,a,b,c,q1,q2\n", 1, "no 'plane' column");
  expect_bad("plane,x,y,z,a,b,c,q1,q2\n", 1, "no 'distance' column");
}

TEST_CASE("calibration csv: each bad row is reported with its line and what is wrong") {
  const std::string head = kPoseHeader + kGoodPoseRow;  // the bad row is line 3
  expect_bad(head + "w,0.25,-200,-200,0,0,0,0,0,700\n", 3, "'w' is not x, y or z");
  expect_bad(head + "z,abc,-200,-200,0,0,0,0,0,700\n", 3, "column 'distance': 'abc' is not a");
  expect_bad(head + "z,nan,-200,-200,0,0,0,0,0,700\n", 3, "not a finite number");
  expect_bad(head + "z,,-200,-200,0,0,0,0,0,700\n", 3, "column 'distance' is empty");
  expect_bad(head + "z,0.1,-200,-200,0,0,0,0,0,700,5\n", 3, "expected 10 fields");
  expect_bad(head + "z,0.1,-200,-200,0,0,0\n", 3, "expected 10 fields");
  expect_bad(head + "z,0.1,-200,1e,0,0,0,0,0,700\n", 3, "column 'y': '1e' is not a number");
  expect_bad(head + "z,0.1,-200,-200,0,0,0,0,0,x\n", 3, "column 'q2'");
  expect_bad(head + "\n# a comment\nz,0.1,5000,-200,0,0,0,0,0,700\n", 5, "cannot be reached");
  expect_bad(head + "z,0.1,-200,-200,0,0,0,0,0,99999\n", 3, "beyond the joints' limits");
  std::string joints_row = "y,0.5";
  for (int i = 0; i < andres().size(); ++i)
    joints_row += i == 4 ? ",q" : ",0";
  expect_bad(joints_header() + joints_row + "\n", 2, "column 'q5': 'q' is not a number");
}

TEST_CASE("calibration csv: columns in any order, any case, CRLF line ends") {
  const std::string text =
      "Q2 , Plane,X,y,z,a,b,c,q1,DISTANCE\r\n700,z,-200,-200,0,0,0,0,0,0.25\r\n";
  const auto pts = parse_readings_csv(text, "r.csv", andres());
  REQUIRE(pts.size() == 1);
  CHECK(pts[0].plane == PlaneAxis::z);
  CHECK(pts[0].reading_mm == 0.25);
  CHECK(pts[0].q[0] == 0.0);
  CHECK(pts[0].q[1] == 700.0);
}

TEST_CASE("calibration csv: the calibrated cell XML changes only the identified values") {
  const std::string path = test::source_path("definitions/cells/andres2011_kr15_track_table.xml");
  const std::string xml = read_text_file(path);
  const auto params = parse_calibration_parameters("link1.d,link2.theta,link8.alpha", andres());
  Eigen::VectorXd v = parameter_values(andres(), params);
  v[0] += 0.4;
  v[1] += deg_to_rad(0.01);
  v[2] -= 1e-4;
  const std::string out = calibrated_cell_xml(xml, path, params, v, "calibrated -- test");
  CHECK(out.find("<!-- calibrated - - test -->\n<cell ") != std::string::npos);
  CHECK(out.find(R"(<dh alpha="90" a="803" theta="0" d="-304.6"/>)") != std::string::npos);
  CHECK(out.find(R"(<dh alpha="90" a="0" theta="0.01" d="0"/>)") != std::string::npos);
  const Cell back = parse_cell(out, "calibrated.xml");
  CHECK((parameter_values(back, params) - v).cwiseAbs().maxCoeff() < 1e-12);
  // Every other parameter is untouched.
  for (int i = 0; i < andres().size(); ++i) {
    const Joint& a = andres().joint(i);
    const Joint& b = back.joint(i);
    if (i != 0)
      CHECK(a.d_mm == b.d_mm);
    if (i != 1)
      CHECK(a.theta_rad == b.theta_rad);
    if (i != 7)
      CHECK(a.alpha_rad == b.alpha_rad);
    CHECK(a.a_mm == b.a_mm);
  }
  // Removing the edited lines and the comment gives the original text back, byte for byte.
  auto strip = [](const std::string& s) {
    std::string r;
    size_t pos = 0;
    while (pos < s.size()) {
      size_t e = s.find('\n', pos);
      e = e == std::string::npos ? s.size() : e + 1;
      const std::string line = s.substr(pos, e - pos);
      if (line.find("<dh") == std::string::npos && line.find("calibrated") == std::string::npos)
        r += line;
      pos = e;
    }
    return r;
  };
  CHECK(strip(out) == strip(xml));
}
