// The training driver's data side (core/training/dataset.hpp): class folders and manifests become labelled items,
// a describer's samples and losses are collected per item (in item order, whatever the worker count), and every
// loss is counted in the per-class table.
#include "core/training/dataset.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include "core/common/errors.hpp"

namespace wish {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("wish_dataset_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }
  void touch(const fs::path& rel) const {
    fs::create_directories((path_ / rel).parent_path());
    std::ofstream(path_ / rel) << "x";
  }

 private:
  fs::path path_;
};

TEST(Dataset, ClassFoldersBecomeLabelledItemsSortedAndFiltered) {
  TempDir dir;
  dir.touch("sphere/b.obj");
  dir.touch("sphere/a.PLY");
  dir.touch("sphere/README.md");     // not an input: ignored
  dir.touch("cube/c.stl");
  dir.touch("cube/d.off");
  dir.touch("volumes/cells.nii.gz");
  dir.touch("volumes/stack.tif");
  dir.touch("volumes/notes.csv");
  fs::create_directories(dir.path() / "empty");  // a class folder without inputs is skipped
  dir.touch("top-level.obj");                     // not in a class folder: ignored

  const auto items = list_class_directories(dir.path());
  ASSERT_EQ(items.size(), 6u);
  std::vector<std::pair<std::string, std::string>> got;
  for (const auto& it : items) {
    got.emplace_back(fs::path(it.path).filename().string(), it.label);
    EXPECT_TRUE(it.object_labels.empty());
  }
  const std::vector<std::pair<std::string, std::string>> want{{"c.stl", "cube"},        {"d.off", "cube"},
                                                              {"a.PLY", "sphere"},      {"b.obj", "sphere"},
                                                              {"cells.nii.gz", "volumes"}, {"stack.tif", "volumes"}};
  EXPECT_EQ(got, want);
}

TEST(Dataset, ManifestRowsWithLabelIdsGroupByVolume) {
  const std::string csv =
      "path,label,label_id\n"
      "meshes/a.obj,sphere\n"
      "vol/v1.nii.gz,mito,3\n"
      "/abs/b.ply,cube,\n"
      "vol/v1.nii.gz,lyso,7\n"
      "vol/v2.tif,mito,1\n";
  const auto items = read_dataset_manifest(csv, "/data/set");
  ASSERT_EQ(items.size(), 4u);
  EXPECT_EQ(items[0].path, "/data/set/meshes/a.obj");
  EXPECT_EQ(items[0].label, "sphere");
  EXPECT_TRUE(items[0].object_labels.empty());
  EXPECT_EQ(items[1].path, "/data/set/vol/v1.nii.gz");
  EXPECT_EQ(items[1].object_labels, (std::map<std::uint32_t, std::string>{{3, "mito"}, {7, "lyso"}}));
  EXPECT_EQ(items[2].path, "/abs/b.ply");  // an empty label_id is a whole-file row
  EXPECT_TRUE(items[2].object_labels.empty());
  EXPECT_EQ(items[3].object_labels, (std::map<std::uint32_t, std::string>{{1, "mito"}}));
}

TEST(Dataset, ManifestErrorsNameTheLine) {
  auto code_and_message = [](const std::string& csv) -> std::pair<std::string, std::string> {
    try {
      read_dataset_manifest(csv, "/base");
    } catch (const WishError& e) {
      return {e.code(), e.what()};
    }
    return {"", ""};
  };
  auto [c1, m1] = code_and_message("a.obj,x\nonly-a-path\n");
  EXPECT_EQ(c1, "invalid_manifest");
  EXPECT_NE(m1.find("line 2"), std::string::npos) << m1;
  auto [c2, m2] = code_and_message("v.nii,x,-4\n");
  EXPECT_EQ(c2, "invalid_manifest");
  EXPECT_NE(m2.find("label_id '-4'"), std::string::npos) << m2;
  auto [c3, m3] = code_and_message("v.nii,x,0\n");  // 0 is the background of a label image
  EXPECT_EQ(c3, "invalid_manifest");
  auto [c4, m4] = code_and_message("v.nii,x,5\nv.nii,y,5\n");
  EXPECT_EQ(c4, "invalid_manifest");
  EXPECT_NE(m4.find("listed twice"), std::string::npos) << m4;
  auto [c5, m5] = code_and_message("a.obj,\n");
  EXPECT_EQ(c5, "invalid_manifest");
}

// A describer that plays a mesh (one sample), a failing mesh (throws), a volume with a refused object and a
// volume that cannot be read, so every path of describe_dataset runs.
ItemDescription fake_describe(const DatasetItem& item) {
  const std::string name = fs::path(item.path).filename().string();
  if (name.rfind("bad", 0) == 0) throw WishError(ErrorCategory::Unmappable, "genus_nonzero", "genus 1");
  if (name.rfind("unreadable", 0) == 0) throw InvalidInputError("invalid_volume", "truncated header");
  ItemDescription d;
  if (name.rfind("vol", 0) == 0) {
    for (std::uint32_t id : {1u, 2u, 3u}) {
      const std::string id_text = item.path + "#" + std::to_string(id);
      if (id == 2) {
        d.losses.push_back({id_text, item.label, "not_manifold", "object 2"});
      } else {
        TrainingSample s;
        s.id = id_text;
        s.label = item.label;
        s.off_recipe = id == 3;
        d.samples.push_back(s);
      }
    }
    d.status = "3 objects, 1 lost";
    return d;
  }
  TrainingSample s;
  s.id = item.path;
  s.label = item.label;
  d.samples.push_back(s);
  d.status = "ok";
  return d;
}

TEST(Dataset, DescribeCollectsSamplesAndEveryLossInItemOrder) {
  std::vector<DatasetItem> items{{"a/m1.obj", "a", {}},         {"a/bad1.obj", "a", {}}, {"a/m2.obj", "a", {}},
                                 {"b/vol1.nii", "b", {}},       {"b/m3.obj", "b", {}},
                                 {"c/unreadable.nii", "", {{4, "c"}, {9, "d"}}},  // per-object manifest rows
                                 {"d/m4.obj", "d", {}}};
  for (int jobs : {1, 3}) {
    std::vector<std::string> lines;
    int lost_lines = 0;
    DescribeSetOptions o;
    o.jobs = jobs;
    o.progress = [&](const std::string& line, bool lost) {
      lines.push_back(line);
      lost_lines += lost;
    };
    const TrainingSet set = describe_dataset(items, fake_describe, o);
    std::vector<std::string> ids;
    for (const auto& s : set.samples) ids.push_back(s.id);
    EXPECT_EQ(ids, (std::vector<std::string>{"a/m1.obj", "a/m2.obj", "b/vol1.nii#1", "b/vol1.nii#3", "b/m3.obj", "d/m4.obj"}))
        << "jobs " << jobs;
    ASSERT_EQ(set.losses.size(), 4u);
    EXPECT_EQ(set.losses[0].id, "a/bad1.obj");
    EXPECT_EQ(set.losses[0].code, "genus_nonzero");
    EXPECT_EQ(set.losses[1].id, "b/vol1.nii#2");
    // An unreadable volume listed by object loses each object with its own class.
    EXPECT_EQ(set.losses[2].id, "c/unreadable.nii#4");
    EXPECT_EQ(set.losses[2].label, "c");
    EXPECT_EQ(set.losses[3].id, "c/unreadable.nii#9");
    EXPECT_EQ(set.losses[3].label, "d");
    EXPECT_EQ(set.losses[3].code, "invalid_volume");
    EXPECT_EQ(lines.size(), items.size());
    EXPECT_EQ(lost_lines, 3);  // bad1, vol1, unreadable
    for (const auto& l : lines) EXPECT_EQ(l.front(), '[') << l;

    const auto table = summarize_training_set(set);
    std::map<std::string, ClassLosses> by;
    for (const auto& c : table) by[c.label] = c;
    ASSERT_EQ(by.size(), 4u);
    EXPECT_EQ(by["a"].total, 3);
    EXPECT_EQ(by["a"].kept, 2);
    EXPECT_EQ(by["a"].lost_by_code["genus_nonzero"], 1);
    EXPECT_EQ(by["b"].total, 4);  // 3 objects + 1 mesh
    EXPECT_EQ(by["b"].kept, 3);
    EXPECT_EQ(by["b"].flagged, 1);
    EXPECT_EQ(by["b"].lost_by_code["not_manifold"], 1);
    EXPECT_EQ(by["c"].total, 1);
    EXPECT_EQ(by["c"].kept, 0);
    EXPECT_EQ(by["d"].total, 2);
    EXPECT_EQ(by["d"].kept, 1);
  }
}

TEST(Dataset, OtherExceptionsPropagate) {
  std::vector<DatasetItem> items{{"x.obj", "a", {}}};
  EXPECT_THROW(describe_dataset(items, [](const DatasetItem&) -> ItemDescription { throw std::logic_error("bug"); }),
               std::logic_error);
}

}  // namespace
}  // namespace wish
