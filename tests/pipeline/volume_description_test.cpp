// describe_volume (core/pipeline/volume_description.hpp), the one owner of a label-volume object: every kept object
// is handed on once with its surface figures and either the work's result or its error; a refused surface carries
// its code's category from the code table; the work's failures are the object's, except a timeout or cancellation;
// the deadline is checked before each object's work.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "core/common/error_codes.hpp"
#include "core/io/volume_io.hpp"
#include "core/pipeline/volume_description.hpp"

namespace wish {
namespace {

// Two balls of radius 5 voxels (labels 1 and 2) side by side, spacing (1, 1, 2): NIfTI bytes.
std::string two_balls() {
  volume::LabelImage image;
  image.dims = {36, 16, 10};
  image.spacing = Eigen::Vector3d(1, 1, 2);
  image.unit = "nm";
  image.labels.assign(static_cast<std::size_t>(image.voxel_count()), 0);
  for (std::int64_t z = 0; z < image.dims[2]; ++z)
    for (std::int64_t y = 0; y < image.dims[1]; ++y)
      for (std::int64_t x = 0; x < image.dims[0]; ++x)
        for (std::uint32_t label : {1u, 2u}) {
          const Eigen::Vector3d c(label == 1 ? 8 : 26, 8, 10);
          const Eigen::Vector3d p(x, y, 2.0 * static_cast<double>(z));
          if ((p - c).norm() <= 5.0) image.labels[image.index(x, y, z)] = label;
        }
  return write_nifti(image);
}

struct Seen {
  std::vector<std::uint32_t> ids;
  std::vector<VolumeObjectResult> objects;
};

ObjectResultCallback keep(Seen& seen) {
  return [&seen](std::size_t index, VolumeObjectResult& object) {
    EXPECT_EQ(index, seen.objects.size());  // in order, each once
    seen.ids.push_back(object.object.id);
    seen.objects.push_back(object);
  };
}

TEST(DescribeVolume, EveryObjectOnceWithItsSurfaceFigures) {
  Seen seen;
  int worked = 0;
  const VolumeSummary summary = describe_volume(
      two_balls(), {},
      [&](const volume::VolumeObject&, Mesh mesh) -> std::optional<PipelineResult> {
        ++worked;
        EXPECT_GT(mesh.vertex_count(), 0);  // the accepted surface itself is the work's
        return std::nullopt;
      },
      keep(seen));
  EXPECT_EQ(summary.kept, 2);
  EXPECT_EQ(worked, 2);
  ASSERT_EQ(seen.ids, (std::vector<std::uint32_t>{1, 2}));
  for (const VolumeObjectResult& o : seen.objects) {
    EXPECT_TRUE(o.ok());
    EXPECT_EQ(o.surface.genus, 0);
    EXPECT_GT(o.surface.vertices, 0);  // kept although the mesh moved on to the work
    // Physical units: each voxel is 1 x 1 x 2.
    EXPECT_NEAR(o.surface.voxel_volume, 2.0 * static_cast<double>(o.object.voxel_count),
                0.2 * static_cast<double>(o.object.voxel_count));
  }
}

TEST(DescribeVolume, ARefusedSurfaceCarriesItsCodesCategory) {
  VolumeOptions options;
  options.surface.max_box_voxels = 50;  // both balls' boxes are larger
  Seen seen;
  describe_volume(
      two_balls(), options,
      [](const volume::VolumeObject&, Mesh) -> std::optional<PipelineResult> {
        ADD_FAILURE() << "a refused surface reached the work";
        return std::nullopt;
      },
      keep(seen));
  ASSERT_EQ(seen.objects.size(), 2u);
  for (const VolumeObjectResult& o : seen.objects) {
    ASSERT_FALSE(o.ok());
    EXPECT_EQ(o.error->code(), "box_too_large");
    // The code table's category (413 in the service), not the Unmappable every refusal used to get in the CLI.
    EXPECT_EQ(o.error->category(), ErrorCategory::TooLarge);
    EXPECT_EQ(find_error_code("box_too_large")->category, ErrorCategory::TooLarge);
    EXPECT_EQ(std::get<std::int64_t>(o.error->details().at("label_id")), o.object.id);
  }
}

TEST(DescribeVolume, AWorkFailureIsTheObjectsButATimeoutEndsTheVolume) {
  Seen seen;
  describe_volume(
      two_balls(), {},
      [](const volume::VolumeObject& object, Mesh) -> std::optional<PipelineResult> {
        if (object.id == 1) throw WishError(ErrorCategory::Unmappable, "map_failed", "no map");
        return std::nullopt;
      },
      keep(seen));
  ASSERT_EQ(seen.objects.size(), 2u);
  EXPECT_EQ(seen.objects[0].error->code(), "map_failed");
  EXPECT_TRUE(seen.objects[1].ok());  // the other object is unaffected

  Seen after_timeout;
  EXPECT_THROW(describe_volume(
                   two_balls(), {},
                   [](const volume::VolumeObject&, Mesh) -> std::optional<PipelineResult> {
                     throw TimeoutError("time limit exceeded during map");
                   },
                   keep(after_timeout)),
               TimeoutError);
  EXPECT_TRUE(after_timeout.objects.empty());
}

TEST(DescribeVolume, TheDeadlineIsCheckedBeforeEachObject) {
  const auto no_work = [](const volume::VolumeObject&, Mesh) -> std::optional<PipelineResult> {
    ADD_FAILURE() << "worked past the deadline";
    return std::nullopt;
  };
  Seen seen;
  try {
    describe_volume(two_balls(), {}, no_work, keep(seen), Deadline::after(std::chrono::seconds(0)));
    FAIL() << "no timeout";
  } catch (const WishError& e) {
    EXPECT_EQ(e.category(), ErrorCategory::Timeout);
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("objects_done")), 0);
    EXPECT_EQ(std::get<std::int64_t>(e.details().at("objects")), 2);
  }
  Deadline cancelled;
  auto flag = std::make_shared<std::atomic<bool>>(true);
  cancelled.attach_cancel_flag(flag);
  try {
    describe_volume(two_balls(), {}, no_work, keep(seen), cancelled);
    FAIL() << "not cancelled";
  } catch (const WishError& e) {
    EXPECT_EQ(e.code(), "cancelled");  // a cancellation stays one (503), not a timeout
  }
  EXPECT_TRUE(seen.objects.empty());
}

TEST(DescribeVolume, NoObjectLeftIsItsOwnRefusal) {
  VolumeOptions options;
  options.objects.min_voxels = 1'000'000;
  const VolumeSummary s = describe_volume(
      two_balls(), options, [](const volume::VolumeObject&, Mesh) { return std::optional<PipelineResult>{}; },
      [](std::size_t, VolumeObjectResult&) { ADD_FAILURE() << "an object past the filter"; });
  EXPECT_EQ(s.kept, 0);
  const WishError e = no_objects_error(s);
  EXPECT_EQ(e.code(), "no_objects");
  EXPECT_EQ(std::get<std::int64_t>(e.details().at("small")), 2);
}

}  // namespace
}  // namespace wish
