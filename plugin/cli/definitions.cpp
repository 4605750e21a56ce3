#include "definitions.hpp"

#include <unistd.h>

#include <filesystem>
#include <system_error>

namespace redpost::cli {

std::string definitions_dir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share/redpost/definitions";
    if (fs::is_directory(installed, ec))
      return installed.string();
  }
  return REDPOST_SOURCE_DEFINITIONS_DIR;
}

std::string default_krl_template() {
  return definitions_dir() + "/krl/krc4_lin.xml";
}

}  // namespace redpost::cli
