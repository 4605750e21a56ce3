// Loads an installed cell and prints the TCP at home: proves headers, library, dependencies
// and data all install together.
#include <cmath>
#include <cstdio>

#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"

int main() {
  const redpost::Cell cell = redpost::load_cell(REDPOST_CELL);
  const Eigen::Vector3d p = redpost::tcp_pose(cell, cell.home()).translation();
  std::printf("%s home TCP %.3f %.3f %.3f\n", cell.name.c_str(), p.x(), p.y(), p.z());
  // KR15/2 HOME puts $FLANGE at X1040 Y0 Z1480 (PARAMETERS.md 2.2).
  return std::fabs(p.x() - 1040) < 1e-6 && std::fabs(p.z() - 1480) < 1e-6 ? 0 : 1;
}
