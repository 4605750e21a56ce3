// Where the shipped definitions (cells, KRL template sets) are: next to the installed binary
// (PREFIX/share/redpost/definitions) or, when run from the build tree, in the source tree.
#pragma once

#include <string>

namespace redpost::cli {

std::string definitions_dir();
std::string default_krl_template();  // definitions_dir()/krl/krc4_lin.xml

}  // namespace redpost::cli
