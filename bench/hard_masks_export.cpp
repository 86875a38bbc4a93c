// Writes the hard single-object masks of tests/synth/hard_masks.hpp as 8-bit .nii.gz, so that the CLI can be run on
// them as a user runs it (docs/accuracy.md, "Hard single-object masks"):
//   hard_masks_export OUTDIR
//     OUTDIR/masks/<family>__<name>.nii.gz      the 60 generated masks (wish mesh-labels OUTDIR/masks/*.nii.gz ...)
//     OUTDIR/train/<class>/<class>_<seed>.nii.gz 12 soft-edged demo cells with 6 specks each per class
//                                                (wish train OUTDIR/train: one sample per file, no flags)
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/io/volume_io.hpp"
#include "core/synth/nucleus_shape.hpp"
#include "tests/synth/hard_masks.hpp"

namespace fs = std::filesystem;

namespace {

void write(const fs::path& path, const wish::volume::LabelImage& image) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << wish::write_nifti(image, "uint8", true);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: hard_masks_export OUTDIR\n");
    return 2;
  }
  const fs::path out = argv[1];
  int n = 0;
  for (const auto& m : wish::testing::generated_hard_masks()) {
    write(out / "masks" / (m.family + "__" + m.name + ".nii.gz"), m.image);
    ++n;
  }
  for (int cls = 0; cls < 6; ++cls)
    for (int k = 0; k < 12; ++k) {
      const auto m = wish::testing::soft_demo_mask(cls, 500 + 17 * static_cast<std::uint64_t>(k) + static_cast<std::uint64_t>(cls), 6);
      write(out / "train" / wish::synth::demo_classes()[static_cast<std::size_t>(cls)] / (m.name + ".nii.gz"), m.image);
      ++n;
    }
  std::printf("%d masks written under %s\n", n, out.c_str());
  return 0;
}
