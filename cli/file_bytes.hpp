#pragma once
// The whole content of a file the user named on the command line, or IoError("file_not_found") naming
// it: the one way every subcommand reads its inputs.

#include <fstream>
#include <sstream>
#include <string>

#include "core/common/errors.hpp"

namespace wish::cli {

inline std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("file_not_found", "cannot open '" + path + "'", {{"file", path}});
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace wish::cli
