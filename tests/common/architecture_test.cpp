// The rules of docs/architecture.md as tests (issue 27), read from the source tree (WISH_TEST_SOURCE_DIR):
//  * the include matrix: core never includes wire, server or cli; wire never server or cli; cli never server and
//    server never cli (`wish serve` runs the wish-server executable); inside core an area includes only areas below it, in the order
//    docs/architecture.md draws (read from that file, so the drawing and the test are one rule);
//  * every repository path a source comment names exists in the tree, a design note is cited by its path
//    (docs/design/<note>.md), and nothing outside the repository is cited except the shared test data
//    (../shared/data, which tests skip without).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kSource = WISH_TEST_SOURCE_DIR;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The repository's own folders (everything else at the top — build trees, caches — is not the repository's).
const std::vector<std::string> kTopFolders{"bench", "cli",  "clients", "cmake",  "core",   "data", "docker",
                                           "docs",  "proto", "scripts", "server", "tests", "web",  "wire"};

bool skipped_folder(const fs::path& p) {
  const std::string name = p.filename().string();
  return name == "node_modules" || name == "__pycache__" || name == "build" || name.ends_with(".egg-info") ||
         name.starts_with(".");
}

// Every file of the repository's folders (relative, '/'-separated), plus the top-level files.
const std::vector<std::string>& tree() {
  static const std::vector<std::string> files = [] {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(kSource))
      if (e.is_regular_file()) out.push_back(e.path().filename().string());
    for (const auto& top : kTopFolders) {
      if (!fs::exists(kSource / top)) continue;
      out.push_back(top + "/");
      for (auto it = fs::recursive_directory_iterator(kSource / top); it != fs::recursive_directory_iterator(); ++it) {
        if (it->is_directory() && skipped_folder(it->path())) {
          it.disable_recursion_pending();
          continue;
        }
        out.push_back(fs::relative(it->path(), kSource).generic_string() + (it->is_directory() ? "/" : ""));
      }
    }
    std::sort(out.begin(), out.end());
    return out;
  }();
  return files;
}

// ---- (a) the include matrix ----

struct Include {
  std::string file;  // including file, relative
  int line;
  std::string header;  // as written: "core/classify/classifier_model.hpp"
};

std::vector<Include> includes_under(const std::string& folder) {
  static const std::regex include_rx(R"(^\s*#\s*include\s*"([^"]+)\")");
  std::vector<Include> out;
  for (const auto& file : tree()) {
    if (!file.starts_with(folder + "/") || file.ends_with("/")) continue;
    if (!file.ends_with(".cpp") && !file.ends_with(".hpp") && !file.ends_with(".h") && !file.ends_with(".in"))
      continue;
    const auto lines = lines_of(read_text(kSource / file));
    for (std::size_t i = 0; i < lines.size(); ++i) {
      std::smatch m;
      if (std::regex_search(lines[i], m, include_rx)) out.push_back({file, static_cast<int>(i + 1), m[1].str()});
    }
  }
  return out;
}

std::string first_segment(const std::string& path, std::size_t skip = 0) {
  std::size_t start = 0;
  for (std::size_t k = 0; k < skip; ++k) start = path.find('/', start) + 1;
  return path.substr(start, path.find('/', start) - start);
}

TEST(Architecture, FoldersIncludeOnlyFoldersBelowThem) {
  if (!fs::exists(kSource / "core")) GTEST_SKIP() << "source tree not found at " << kSource;
  // docs/architecture.md: cli -> (wire, core); server -> (wire, core); wire -> core; core -> nothing above it.
  // (`wish serve` execs the wish-server executable: neither of the two front ends includes the other.)
  const std::map<std::string, std::set<std::string>> forbidden{{"core", {"wire", "server", "cli"}},
                                                               {"wire", {"server", "cli"}},
                                                               {"cli", {"server"}},
                                                               {"server", {"cli"}}};
  std::size_t checked = 0;
  for (const auto& [folder, above] : forbidden) {
    for (const auto& inc : includes_under(folder)) {
      ++checked;
      EXPECT_FALSE(above.count(first_segment(inc.header)))
          << inc.file << ":" << inc.line << " includes " << inc.header << ": " << folder << " must not include "
          << first_segment(inc.header) << " (docs/architecture.md)";
    }
  }
  EXPECT_GT(checked, 200u) << "too few includes found: has the layout changed?";
}

// The core areas in the order docs/architecture.md draws them ("pipeline → classify → ... → common"; areas on one
// level are separated by '/'): rank 0 is the top.
std::map<std::string, int> core_area_ranks() {
  const std::string doc = read_text(kSource / "docs" / "architecture.md");
  std::map<std::string, int> ranks;
  for (const auto& line : lines_of(doc)) {
    if (line.find("pipeline →") == std::string::npos) continue;
    std::string rest = line;
    int rank = 0;
    for (std::size_t pos; !rest.empty(); ++rank) {
      pos = rest.find("→");
      std::string level = rest.substr(0, pos);
      rest = pos == std::string::npos ? "" : rest.substr(pos + std::string("→").size());
      std::stringstream names(level);
      for (std::string name; std::getline(names, name, '/');) {
        name.erase(0, name.find_first_not_of(' '));
        name.erase(name.find_last_not_of(' ') + 1);
        if (!name.empty()) ranks[name] = rank;
      }
    }
    break;
  }
  return ranks;
}

TEST(Architecture, CoreAreasIncludeOnlyAreasBelowThem) {
  if (!fs::exists(kSource / "docs" / "architecture.md")) GTEST_SKIP() << "source tree not found at " << kSource;
  const auto ranks = core_area_ranks();
  ASSERT_GE(ranks.size(), 10u) << "the core area order (\"pipeline → classify → ...\") not found in docs/architecture.md";
  for (const auto& dir : fs::directory_iterator(kSource / "core")) {
    if (!dir.is_directory()) continue;
    EXPECT_TRUE(ranks.count(dir.path().filename().string()))
        << "core/" << dir.path().filename().string() << " is not placed in docs/architecture.md's area order";
  }
  for (const auto& inc : includes_under("core")) {
    if (!inc.header.starts_with("core/")) continue;
    const std::string from = first_segment(inc.file, 1), to = first_segment(inc.header, 1);
    if (from == to || !ranks.count(from) || !ranks.count(to)) continue;
    EXPECT_LT(ranks.at(from), ranks.at(to))
        << inc.file << ":" << inc.line << " includes " << inc.header << ": core/" << from << " is not above core/"
        << to << " in docs/architecture.md";
  }
}

// ---- (b) paths named in comments ----

struct Comment {
  std::string file;
  int line;
  std::string text;
};

// The comments of the repository's source files: `//` in C++ and JavaScript, `#` in Python, shell and CMake.
std::vector<Comment> comments() {
  std::vector<Comment> out;
  for (const auto& file : tree()) {
    if (file.ends_with("/")) continue;
    const std::string ext = fs::path(file).extension().string();
    const std::string name = fs::path(file).filename().string();
    const bool slashes = ext == ".cpp" || ext == ".hpp" || ext == ".h" || ext == ".in" || ext == ".js" || ext == ".mjs";
    const bool hash = ext == ".py" || ext == ".sh" || ext == ".cmake" || name == "CMakeLists.txt" || name == "Dockerfile";
    if (!slashes && !hash) continue;
    const auto lines = lines_of(read_text(kSource / file));
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const std::size_t at = slashes ? lines[i].find("//") : lines[i].find('#');
      if (at != std::string::npos) out.push_back({file, static_cast<int>(i + 1), lines[i].substr(at)});
    }
  }
  return out;
}

std::string regex_of_glob(const std::string& glob) {
  std::string rx;
  for (std::size_t i = 0; i < glob.size(); ++i) {
    const char c = glob[i];
    if (c == '*' && i + 1 < glob.size() && glob[i + 1] == '*') {
      rx += ".*";
      ++i;
    } else if (c == '*') {
      rx += "[^/]*";
    } else if (std::string(".+?()[]{}|^$\\").find(c) != std::string::npos) {
      rx += std::string("\\") + c;
    } else {
      rx += c;
    }
  }
  return rx;
}

// A path as a comment writes it: a file or folder, `name.*` / `name` for a file's parts (name.hpp and name.cpp), a
// glob (`cli/cmd_*.cpp`), or `{a,b}` alternatives — each alternative must exist.
bool exists_in_tree(const std::string& path) {
  const auto open = path.find('{');
  const auto close = path.find('}', open == std::string::npos ? 0 : open);
  if (open != std::string::npos && close != std::string::npos) {
    std::stringstream alternatives(path.substr(open + 1, close - open - 1));
    bool all = true;
    for (std::string alt; std::getline(alternatives, alt, ',');)
      all = all && exists_in_tree(path.substr(0, open) + alt + path.substr(close + 1));
    return all;
  }
  std::string p = path;
  if (p.ends_with(".*")) p.resize(p.size() - 2);
  const auto& files = tree();
  if (p.find('*') != std::string::npos) {
    const std::regex rx(regex_of_glob(p) + "/?");
    return std::any_of(files.begin(), files.end(), [&](const std::string& f) { return std::regex_match(f, rx); });
  }
  if (std::binary_search(files.begin(), files.end(), p) || std::binary_search(files.begin(), files.end(), p + "/"))
    return true;
  // `core/training/dataset` or `core/common/thread_policy.*`: the name of a header / source pair.
  const auto it = std::lower_bound(files.begin(), files.end(), p + ".");
  return it != files.end() && it->starts_with(p + ".") && it->find('/', p.size()) == std::string::npos;
}

TEST(Architecture, EveryPathNamedInACommentExists) {
  if (!fs::exists(kSource / "core")) GTEST_SKIP() << "source tree not found at " << kSource;
  std::string tops;
  for (const auto& t : kTopFolders) tops += (tops.empty() ? "" : "|") + t;
  // A path: a top folder of the repository or ../, then segments; not inside a URL or a longer path.
  const std::regex path_rx("(^|[^A-Za-z0-9_/.-])((?:\\.\\./)+[A-Za-z0-9_.-]+(?:/[A-Za-z0-9_.*{},<>-]+)*|(?:" + tops +
                           ")/[A-Za-z0-9_.*{},<>-]*(?:/[A-Za-z0-9_.*{},<>-]+)*)");
  // Paths of generated files, not in the tree (npm install; the build).
  const std::set<std::string> generated{"web/node_modules"};
  std::set<std::string> design_notes;
  for (const auto& f : tree())
    if (f.starts_with("docs/design/") && f.ends_with(".md")) design_notes.insert(fs::path(f).filename().string());
  ASSERT_FALSE(design_notes.empty()) << "no design notes in docs/design/";
  std::size_t paths = 0;
  for (const auto& c : comments()) {
    for (std::sregex_iterator it(c.text.begin(), c.text.end(), path_rx), end; it != end; ++it) {
      std::string path = (*it)[2].str();
      while (!path.empty() && std::string(".,:;)'`").find(path.back()) != std::string::npos) path.pop_back();
      if (path.find('<') != std::string::npos) continue;  // a placeholder: tests/<area>/*_test.cpp
      ++paths;
      if (generated.count(path)) continue;
      if (path.starts_with("../")) {
        EXPECT_TRUE(path.starts_with("../shared/data"))
            << c.file << ":" << c.line << " cites " << path
            << ", outside the repository: a reader of the repository cannot open it (move it in, or cite the copy)";
        continue;
      }
      EXPECT_TRUE(exists_in_tree(path)) << c.file << ":" << c.line << " names " << path << ", which does not exist";
    }
    // A design note is cited by its path, so that a reader finds it (and this test checks it).
    for (const auto& note : design_notes) {
      for (std::size_t at = c.text.find(note); at != std::string::npos; at = c.text.find(note, at + 1)) {
        const bool by_path = at >= 12 && c.text.compare(at - 12, 12, "docs/design/") == 0;
        const bool longer_name = at > 0 && (std::isalnum(static_cast<unsigned char>(c.text[at - 1])) ||
                                            c.text[at - 1] == '-' || c.text[at - 1] == '_');
        EXPECT_TRUE(by_path || longer_name)
            << c.file << ":" << c.line << " cites the design note " << note << " without its path docs/design/"
            << note;
      }
    }
  }
  std::cout << "checked " << paths << " repository paths named in source comments\n";
  EXPECT_GT(paths, 150u) << "too few paths found in comments: has the scan stopped working?";
}

}  // namespace
