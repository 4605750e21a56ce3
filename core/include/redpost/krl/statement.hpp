// The KRL statements redpost passes through from CL files and hosts (INSERT/KRL:, rp_literal,
// NX's insert event) into a program: one statement a controller accepts and redpost check
// reads, of a small, checked set (docs/cl-format.md, "INSERT"):
//
//   HALT
//   WAIT SEC <number>
//   WAIT FOR [NOT] <variable> [== TRUE|FALSE]
//   <variable> = <value>                 $OUT[17] = TRUE, $VEL.CP = 0.2, MY_FLAG = #ON
//   <name>(<value>, ...)                 TOOL_CHANGE(3), PULSE($OUT[3], TRUE, 0.5), BAS(#VEL_PTP,
//   20)
//
// with an optional "; comment" after it. A variable is NAME or $NAME, with [i] or [i, j] and
// .FIELD parts; a value is a number, TRUE, FALSE, #ENUM, "text" or a variable. Motions,
// declarations, control structures and everything else are refused: a statement that moves
// the robot or changes the program's flow must come from the template set, where it is seen.
#pragma once

#include <string>
#include <string_view>

namespace redpost::krl {

// Empty if `text` is such a statement; else what is wrong with it, in words.
std::string statement_problem(std::string_view text);

}  // namespace redpost::krl
