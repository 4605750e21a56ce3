// What the C ABI tests share: the source tree, the reference cell (Andres 2011's track and
// table) and a NaN.
#pragma once

#include <limits>
#include <string>

namespace redpost::abi_test {

inline const std::string kSource = REDPOST_SOURCE_DIR;
inline const std::string kCell = kSource + "/definitions/cells/andres2011_kr15_track_table.xml";
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace redpost::abi_test
