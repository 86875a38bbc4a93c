// Sweeps over ../shared/data (skipped when absent): every genus-0 mesh is accepted, every negative one refused with
// the code its README / topology.tsv implies, and the report agrees with topology.tsv. Test names start with
// "SlowSharedData" so they can be labelled / filtered as the slow sweeps.
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "core/io/mesh_io.hpp"
#include "core/validation/mesh_report.hpp"
#include "tests/testing/test_data.hpp"

namespace wish {
namespace {

std::string issue_codes(const PreparedMesh& p) {
  std::string out;
  for (const auto& i : p.issues) out += i.code + ": " + i.message + "; ";
  return out;
}

bool has_issue(const PreparedMesh& p, const std::string& code) {
  for (const auto& i : p.issues)
    if (i.code == code) return true;
  return false;
}

void expect_mappable_dir(const std::filesystem::path& dir, std::size_t at_least) {
  const auto files = testing::files_in(dir, {".off", ".obj", ".ply", ".stl"});
  EXPECT_GE(files.size(), at_least) << dir;
  for (const auto& file : files) {
    SCOPED_TRACE(file.string());
    const ReadResult r = read_mesh_file(file);
    const PreparedMesh p = prepare_for_mapping(r.mesh);
    EXPECT_TRUE(p.mappable()) << issue_codes(p);
    EXPECT_EQ(p.report.genus.value_or(-1), 0);
    EXPECT_GT(p.report.signed_volume, 0);
  }
}

TEST(SlowSharedData, CgalGenusZeroClosedAreMappable) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  expect_mappable_dir(*testing::shared_data_dir() / "cgal/genus0_closed", 30);
}

TEST(SlowSharedData, NucleiAndCelegansAreMappable) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto data = *testing::shared_data_dir();
  expect_mappable_dir(data / "nmv_nuclei/nuclei-meshes/hq", 4);
  expect_mappable_dir(data / "nmv_nuclei/nuclei-meshes/lq", 4);
  expect_mappable_dir(data / "celegans_cell", 1);
}

TEST(SlowSharedData, InwardEllipsoidIsFlippedAndReported) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const PreparedMesh p = prepare_for_mapping(read_mesh_file(*testing::shared_data_dir() / "cgal/genus0_closed/ellipe0.003.off").mesh);
  EXPECT_NEAR(p.input_report.signed_volume, -1.47402, 1e-4);
  EXPECT_NEAR(p.report.signed_volume, 1.47402, 1e-4);
  ASSERT_FALSE(p.repairs.empty());
  EXPECT_EQ(p.repairs.front().code, "flipped_orientation");
  EXPECT_TRUE(p.mappable());
}

struct TsvRow {
  std::int64_t vertices, faces, edges, chi, components, boundary, nonmanifold, bad_orient;
  std::string genus;
  double volume, area;
};

std::map<std::string, TsvRow> read_topology_tsv(const std::filesystem::path& path) {
  std::map<std::string, TsvRow> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string file, vused, degenerate, dup;
    TsvRow r;
    s >> file >> r.vertices >> vused >> r.faces >> r.edges >> r.chi >> r.components >> r.boundary >> r.nonmanifold >> r.bad_orient >>
        degenerate >> dup >> r.genus >> r.volume >> r.area;
    rows[file] = r;
  }
  return rows;
}

// The reason each negative mesh is bad, from its README: genus > 0, open, several components, shuffled.
std::string expected_code(const std::string& name, const TsvRow& r) {
  if (name.find("shuffled") != std::string::npos) return "inconsistent_orientation";
  if (r.components > 1) return "multiple_components";
  if (r.boundary > 0) return "not_closed";
  return "genus_nonzero";
}

TEST(SlowSharedData, CgalNegativeAreRefusedWithTheRightCode) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto cgal = *testing::shared_data_dir() / "cgal";
  const auto tsv = read_topology_tsv(cgal / "topology.tsv");
  const auto files = testing::files_in(cgal / "negative", {".off", ".obj", ".ply", ".stl"});
  EXPECT_GE(files.size(), 19u);
  for (const auto& file : files) {
    SCOPED_TRACE(file.string());
    const auto row = tsv.find("negative/" + file.filename().string());
    ASSERT_NE(row, tsv.end());
    const PreparedMesh p = prepare_for_mapping(read_mesh_file(file).mesh);
    EXPECT_FALSE(p.mappable());
    EXPECT_TRUE(has_issue(p, expected_code(file.filename().string(), row->second))) << issue_codes(p);
    if (row->second.genus != "None" && row->second.components == 1) {
      ASSERT_TRUE(p.input_report.genus);
      EXPECT_EQ(std::to_string(*p.input_report.genus), row->second.genus);
    }
    EXPECT_THROW(require_mappable(p), WishError);
  }
}

TEST(SlowSharedData, ReportAgreesWithTopologyTsv) {
  WISH_SKIP_WITHOUT_SHARED_DATA();
  const auto cgal = *testing::shared_data_dir() / "cgal";
  for (const auto& [name, row] : read_topology_tsv(cgal / "topology.tsv")) {
    SCOPED_TRACE(name);
    const MeshReport r = analyze_mesh(read_mesh_file(cgal / name).mesh);
    EXPECT_EQ(r.vertices, row.vertices);
    EXPECT_EQ(r.faces, row.faces);
    EXPECT_EQ(r.edges, row.edges);
    EXPECT_EQ(r.euler_characteristic, row.chi);
    EXPECT_EQ(r.components, row.components);
    EXPECT_EQ(r.boundary_edges, row.boundary);
    EXPECT_EQ(r.nonmanifold_edges, row.nonmanifold);
    EXPECT_EQ(r.orientation_consistent, row.bad_orient == 0);
    EXPECT_NEAR(r.signed_volume, row.volume, 1e-5 * std::abs(row.volume) + 1e-6);
    EXPECT_NEAR(r.area, row.area, 1e-5 * row.area);
  }
}

}  // namespace
}  // namespace wish
