// Shared helpers of the unit tests: where the shipped definitions are, seeded random postures.
#pragma once

#include <random>
#include <string>

#include "redpost/cell.hpp"
#include "redpost/cell_xml.hpp"

namespace redpost::test {

inline std::string source_path(const std::string& relative) {
  return std::string(REDPOST_SOURCE_DIR) + "/" + relative;
}

inline Cell shipped_cell(const std::string& name) {
  return load_cell(source_path("definitions/cells/" + name + ".xml"));
}

inline const char* const kShippedCells[] = {"andres2011_kr15_track_table", "kr15_2",
                                            "caro2014_kr270_table"};

// A posture drawn uniformly within the joint limits.
inline JointVector random_posture(const Cell& cell, std::mt19937_64& rng) {
  JointVector q(cell.size());
  for (int i = 0; i < cell.size(); ++i) {
    std::uniform_real_distribution<double> u(cell.joint(i).lower, cell.joint(i).upper);
    q[i] = u(rng);
  }
  return q;
}

}  // namespace redpost::test
