// Fuzz target: the cell XML loader (cell_xml.hpp). A cell it accepts must also be usable: its
// home posture goes through forward kinematics and the controller-axis mapping.
#include "redpost/kinematics/cell_xml.hpp"
#include "fuzz_support.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return redpost::fuzz::run_one([&] {
    const redpost::Cell cell = redpost::parse_cell(redpost::fuzz::as_text(data, size), "fuzz.xml");
    const redpost::JointVector q = cell.home();
    const redpost::Isometry T_B_tcp = redpost::tcp_pose(cell, q);
    const redpost::AxisValues axes = redpost::to_controller_axes(cell, q);
    (void)T_B_tcp;
    (void)axes;
  });
}
