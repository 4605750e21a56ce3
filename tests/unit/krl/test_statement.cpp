// The KRL statements passed through from CL files and hosts (redpost/krl/statement.hpp): the
// forms a controller accepts and redpost check reads pass, everything else is refused with a
// reason.
#include <string>

#include "catch_compat.hpp"
#include "redpost/krl/statement.hpp"

using redpost::krl::statement_problem;

TEST_CASE("statement: assignments, WAIT, HALT and routine calls pass", "[statement]") {
  for (const char* ok : {"HALT",
                         "halt ; stop here",
                         "WAIT SEC 0.5",
                         "WAIT SEC 2",
                         "WAIT FOR $IN[12]",
                         "WAIT FOR NOT $IN[3]",
                         "WAIT FOR $IN[3] == TRUE",
                         "$OUT[17] = TRUE",
                         "$OUT[17]=FALSE",
                         "$VEL.CP = 0.2",
                         "$APO.CDIS = 1.5 ; blend more",
                         "MY_FLAG = #ON",
                         "COUNTER = -3",
                         "TOOL_DATA[3].X = 12.5",
                         "ARR[1, 2] = 4",
                         "MSG = \"text; not a comment\"",
                         "TOOL_CHANGE(3)",
                         "TOOL_CHANGE( )",
                         "PULSE($OUT[3], TRUE, 0.5)",
                         "BAS(#VEL_PTP, 20)",
                         "SPINDLE_ON(12000, #CW)"}) {
    INFO(ok);
    CHECK(statement_problem(ok).empty());
  }
}

TEST_CASE("statement: motions, flow, declarations and free text are refused", "[statement]") {
  const std::pair<const char*, const char*> bad[] = {
      {"", "empty"},
      {"LIN {X 0}", "is not one of the statements"},
      {"PTP HOME", "is not one of the statements"},
      {"IF $IN[1] THEN", "is not one of the statements"},
      {"DECL INT I", "is not one of the statements"},
      {"GOTO LABEL", "is not one of the statements"},
      {"[HOLDER=C40-32ERP412] 14MM X 60DEG HSS CENTERDRILL", "expected a statement"},
      {"Stock Size X144. Y34. Z170.", "expected '='"},
      {"this is not KRL at all !!", "expected '='"},
      {"$OUT[17] == TRUE", "expected '='"},
      {"$OUT[x] = TRUE", "whole number"},
      {"$OUT[17] = TRUE garbage", "unexpected"},
      {"WAIT SEC", "WAIT SEC"},
      {"WAIT SEC 1e300", "at most 1e9"},
      {"WAIT FOR $IN[1] == MAYBE", "TRUE or FALSE"},
      {"WAIT UNTIL 3", "SEC or FOR"},
      {"TOOL_CHANGE(3", "',' or ')'"},
      {"MSG = \"open", "not closed"},
      {"A\x0c"
       "B = 1",
       "control character"},
      {"A = 1\x1b", "control character"},
  };
  for (const auto& [text, why] : bad) {
    INFO(text);
    const std::string problem = statement_problem(text);
    CHECK(problem.find(why) != std::string::npos);
  }
  CHECK(!statement_problem(std::string(3000, 'A') + " = 1").empty());
}
