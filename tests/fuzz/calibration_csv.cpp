// Fuzz target: the calibration readings CSV (calibration/readings_csv.hpp), read against the Andres
// 2011 cell (both forms: commanded pose with q1,q2, and all nine joints).
#include "fuzz_support.hpp"
#include "redpost/calibration/readings_csv.hpp"
#include "redpost/kinematics/cell_xml.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const redpost::Cell cell = redpost::load_cell(
      redpost::fuzz::source_path("definitions/cells/andres2011_kr15_track_table.xml"));
  return redpost::fuzz::run_one([&] {
    redpost::ReadingsReadOptions options;
    options.perturbed_starts = 2;  // each commanded-pose row is an IK solve: keep it cheap
    redpost::parse_readings_csv(redpost::fuzz::as_text(data, size), "fuzz.csv", cell, options);
  });
}
