// wish-contract-enums: writes the OpenAPI schemas of the core enums (wire/contract_enums.hpp) from their core name
// tables. Run by the build (server/CMakeLists.txt), so that a name added to a core table needs no other edit:
//   wish-contract-enums --write proto/openapi.json         rewrite the file's enum schemas (only if they changed)
//   wish-contract-enums --check proto/openapi.json         exit 1 when they are not the tables'
//   wish-contract-enums --embed TEMPLATE OPENAPI OUT.cpp   the service's embedded document (@WISH_OPENAPI_JSON@)
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "wire/contract_enums.hpp"

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Writes only a changed file (so that nothing depending on it rebuilds), through a rename: two builds of the same
// tree (release and sanitizer) may run this at once.
void write_if_changed(const std::string& path, const std::string& text) {
  if (std::filesystem::exists(path) && read_text(path) == text) return;
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

std::string generated(const std::string& openapi_path) {
  const std::string text = wish::wire::with_contract_enums(read_text(openapi_path));
  if (!nlohmann::json::accept(text)) throw std::runtime_error(openapi_path + ": not valid JSON after the rewrite");
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "--write" && argc == 3) {
      write_if_changed(argv[2], generated(argv[2]));
      return 0;
    }
    if (mode == "--check" && argc == 3) {
      if (generated(argv[2]) == read_text(argv[2])) return 0;
      std::cerr << argv[2] << ": the core enum schemas are not the core name tables'; building the service rewrites "
                   "them (or run wish-contract-enums --write " << argv[2] << ")\n";
      return 1;
    }
    if (mode == "--embed" && argc == 5) {
      std::string text = read_text(argv[2]);
      const std::string placeholder = "@WISH_OPENAPI_JSON@";
      const auto at = text.find(placeholder);
      if (at == std::string::npos) throw std::runtime_error(std::string(argv[2]) + " has no " + placeholder);
      text.replace(at, placeholder.size(), generated(argv[3]));
      write_if_changed(argv[4], text);
      return 0;
    }
    std::cerr << "usage: wish-contract-enums --write OPENAPI | --check OPENAPI | --embed TEMPLATE OPENAPI OUT\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "wish-contract-enums: " << e.what() << "\n";
    return 1;
  }
}
