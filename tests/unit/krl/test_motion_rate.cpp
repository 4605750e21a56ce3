// The motion rate of a written program (redpost/krl/motion_rate.hpp): which motions of a
// program last less than one interpolation cycle, counted by hand.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "catch_compat.hpp"
#include "redpost/krl/check.hpp"
#include "redpost/krl/motion_rate.hpp"
#include "redpost/krl/reader.hpp"

using namespace redpost;

TEST_CASE("motion rate: the motions shorter than a 12 ms cycle at the $VEL.CP in force") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "redpost_motion_rate";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // At 0.1 m/s a cycle is 1.2 mm: 1 mm steps are short, 2 mm ones are not; a turn of 1 deg at
  // 200 deg/s lasts 5 ms, of 3 deg 15 ms; a quarter arc of radius 10 mm (15.7 mm) lasts 7.9 ms
  // at 2 m/s and 15.7 ms at 1 m/s. A LIN after a PTP to axes has no known start.
  std::ofstream(dir / "P.src", std::ios::binary)
      << "DEF P( )\r\n"                                     // 1
         "$VEL.CP = 0.1\r\n"                                // 2
         "PTP {A1 0, A2 -90, A3 90, A4 0, A5 0, A6 0}\r\n"  // 3
         "LIN {X 0, Y 0, Z 0, A 0, B 0, C 0} C_DIS\r\n"     // 4 unmeasured
         "LIN {X 1, Y 0, Z 0, A 0, B 0, C 0} C_DIS\r\n"     // 5 10 ms
         "LIN {X 2, Y 0, Z 0, A 0, B 0, C 0} C_DIS\r\n"     // 6 10 ms
         "LIN {X 4, Y 0, Z 0, A 0, B 0, C 0} C_DIS\r\n"     // 7 20 ms
         "LIN {X 4, Y 0, Z 0, A 0, B 0, C 1} C_DIS\r\n"     // 8 5 ms
         "LIN {X 4, Y 0, Z 0, A 0, B 0, C 4} C_DIS\r\n"     // 9 15 ms
         "LIN {X 14, Y 0, Z 0, A 0, B 0, C 4} C_DIS\r\n"    // 10 100 ms
         "$VEL.CP = 2\r\n"                                  // 11
         "CIRC {X 11.0710678, Y 7.0710678, Z 0}, {X 4, Y 10, Z 0, A 0, B 0, C 4}\r\n"  // 12 7.9 ms
         "$VEL.CP = 1\r\n"                                                             // 13
         "CIRC {X -3.0710678, Y 7.0710678, Z 0}, {X -6, Y 0, Z 0, A 0, B 0, C 4}\r\n"  // 14 15.7 ms
         "END\r\n";
  const KrlProgram program = read_krl_program((dir / "P.src").string());
  const KrlMotionRate rate = krl_motion_rate(program, KrlMotionRateOptions{});
  CHECK(rate.cp_motions == 8);
  CHECK(rate.unmeasured == 1);
  CHECK(rate.below_cycle == 4);
  CHECK(rate.shortest_s == Approx(0.005).epsilon(1e-6));
  CHECK(rate.shortest_line == 8);
  REQUIRE(rate.stretches.size() == 3);
  CHECK(rate.stretches[0].first_line == 5);
  CHECK(rate.stretches[0].last_line == 6);
  CHECK(rate.stretches[0].motions == 2);
  CHECK(rate.stretches[0].shortest_s == Approx(0.010).epsilon(1e-6));
  CHECK(rate.stretches[1].first_line == 8);
  CHECK(rate.stretches[2].first_line == 12);
  CHECK(rate.stretches[2].shortest_s == Approx(0.5 * M_PI * 10.0 / 2000.0).epsilon(1e-6));

  // As `check` gives them: warnings at the stretches' first lines; none with the cycle off.
  KrlCheckOptions o;
  std::vector<std::pair<std::string, KrlMotionRate>> totals;
  o.motion_rates = &totals;
  const std::vector<KrlFinding> f = check_krl((dir / "P.src").string(), o);
  std::vector<int> warned;
  for (const KrlFinding& x : f) {
    UNSCOPED_INFO(x.line << ": " << x.message);
    CHECK(x.warning);
    warned.push_back(x.line);
  }
  CHECK(warned == std::vector<int>{5, 8, 12});
  REQUIRE(totals.size() == 1);
  CHECK(totals[0].second.below_cycle == 4);
  o.motion_rate.interpolation_cycle_s = 0.0;
  CHECK(check_krl((dir / "P.src").string(), o).empty());
  // A 4 ms cycle: only the 1 deg turn is shorter.
  o.motion_rate.interpolation_cycle_s = 0.004;
  CHECK(check_krl((dir / "P.src").string(), o).empty());
  o.motion_rate.interpolation_cycle_s = 0.006;
  REQUIRE(check_krl((dir / "P.src").string(), o).size() == 1);
  fs::remove_all(dir);
}

TEST_CASE("motion rate: SPLINE segments joined smoothly are one path; WITH $VEL.CP is theirs") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "redpost_motion_rate_spline";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // At 0.1 m/s a cycle is 1.2 mm. In the first block, 1 mm SPL segments (and the SLIN before
  // them, which an SPL joins) are one path: not counted. The block's last segment has its own
  // speed, 0.2 m/s: 2 mm lasts 10 ms. The second block's lone 1 mm SLIN is a motion of its own.
  std::ofstream(dir / "P.src", std::ios::binary)
      << "DEF P( )\r\n"                                                    // 1
         "$VEL.CP = 0.1\r\n"                                               // 2
         "LIN {X 0, Y 0, Z 0, A 0, B 0, C 0}\r\n"                          // 3 unmeasured
         "SPLINE\r\n"                                                      // 4
         "SLIN {X 1, Y 0, Z 0, A 0, B 0, C 0}\r\n"                         // 5 joined
         "SPL {X 2, Y 0.1, Z 0, A 0, B 0, C 0}\r\n"                        // 6 joined
         "SPL {X 3, Y 0.3, Z 0, A 0, B 0, C 0}\r\n"                        // 7 joined
         "SLIN {X 5, Y 0.3, Z 0, A 0, B 0, C 0} WITH $VEL.CP = 0.2\r\n"    // 8 joined (by 7)
         "SLIN {X 25, Y 0.3, Z 0, A 0, B 0, C 0}\r\n"                      // 9 200 ms
         "ENDSPLINE C_SPL\r\n"                                             // 10
         "SPLINE\r\n"                                                      // 11
         "SLIN {X 26, Y 0.3, Z 0, A 0, B 0, C 0} WITH $VEL.CP = 0.05\r\n"  // 12 20 ms
         "SLIN {X 27, Y 0.3, Z 0, A 0, B 0, C 0}\r\n"                      // 13 10 ms
         "ENDSPLINE C_SPL\r\n"                                             // 14
         "END\r\n";
  const KrlProgram program = read_krl_program((dir / "P.src").string());
  REQUIRE(program.motions.size() == 8);
  CHECK(program.motions[0].spline_block == 0);
  CHECK(program.motions[1].spline_block == 1);
  CHECK(program.motions[5].spline_block == 1);
  CHECK(program.motions[6].spline_block == 2);
  CHECK(program.motions[4].vel_cp_m_per_s == 0.2);  // its own
  CHECK(program.motions[5].vel_cp_m_per_s == 0.1);  // the $VEL.CP in force again
  CHECK(program.motions[6].vel_cp_m_per_s == 0.05);
  CHECK(program.motions[7].vel_cp_m_per_s == 0.1);
  const KrlMotionRate rate = krl_motion_rate(program, KrlMotionRateOptions{});
  CHECK(rate.cp_motions == 7);
  CHECK(rate.unmeasured == 1);
  CHECK(rate.spline_joined == 4);
  CHECK(rate.below_cycle == 1);
  CHECK(rate.shortest_line == 13);
  CHECK(rate.shortest_s == Approx(0.010).epsilon(1e-6));
  fs::remove_all(dir);
}
