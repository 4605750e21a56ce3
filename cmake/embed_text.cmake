# Writes a C++ source that holds a text file as a string (cmake -P, at build time):
#   cmake -DINPUT=file.js -DOUTPUT=file.cpp -DSYMBOL=name -DNAMESPACE=ns -P embed_text.cmake
# The reports inline three.js this way from Debian's libjs-three: read from the installed
# package when redpost is built, never copied into the repository.
foreach(var INPUT OUTPUT SYMBOL NAMESPACE)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "embed_text.cmake: ${var} is not set")
  endif()
endforeach()
file(READ "${INPUT}" content)
# A raw string literal cannot hold its own closing delimiter; an inline <script> cannot hold
# "</script" (the HTML parser would end the element there).
string(FIND "${content}" ")rp_embed\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "embed_text.cmake: ${INPUT} holds the delimiter )rp_embed\"")
endif()
string(TOLOWER "${content}" lower)
string(FIND "${lower}" "</script" script_end)
if(NOT script_end EQUAL -1)
  message(FATAL_ERROR "embed_text.cmake: ${INPUT} holds </script and cannot be inlined")
endif()
# GCC takes long literals, but the standard only promises 65 536 characters: split the text in
# concatenated pieces well under that.
string(LENGTH "${content}" length)
set(pieces "")
set(at 0)
while(at LESS length)
  string(SUBSTRING "${content}" ${at} 30000 piece)
  string(APPEND pieces "R\"rp_embed(${piece})rp_embed\"\n")
  math(EXPR at "${at} + 30000")
endwhile()
if(pieces STREQUAL "")
  set(pieces "\"\"")
endif()
file(WRITE "${OUTPUT}.tmp" "// Generated from ${INPUT} by cmake/embed_text.cmake; do not edit.
namespace ${NAMESPACE} {
extern const char* const ${SYMBOL};
const char* const ${SYMBOL} =
${pieces};
}  // namespace ${NAMESPACE}
")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
