#pragma once
// Hard single-object masks (issue 39 item 1), made in the test tree, never bundled: each is ONE object as a lab saves
// it, and the default path (no flags) must find exactly one object in it and mesh it genus 0.
//   * balls and ellipsoids drilled by 1–5 straight tunnels of 1–3 voxels (genus 1–5);
//   * Y-shaped masks whose two upper limbs bend back and touch (a loop: genus 1), limbs 2–4 voxels thick;
//   * cells with 1–3 internal cavities;
//   * soft-edged single cells with specks: a demo nucleus shape (core/synth/nucleus_shape.hpp) or a UroCell object,
//     resampled into 64³ with trilinear interpolation and stored 8-bit (0–255, grey edges), plus isolated specks
//     above the threshold far from the cell and near it (as a threshold leaves them).
// All masks are 64³ (the held-out sets' size), uint8, the object's value 255, spacing 1 unless said.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/volume/label_image.hpp"

namespace wish::testing {

struct HardMask {
  std::string family;  // "drilled", "y_touch", "cavities", "soft_demo", "soft_urocell"
  std::string name;    // unique, file-name safe
  volume::LabelImage image;
  int expected_genus = -1;  // of the voxel object as made (-1: not known in advance)
};

constexpr int kHardMaskSize = 64;

// k tunnels (1..5) of width w (1..3) through a ball (ellipsoid when `ellipsoid`).
HardMask drilled_mask(int tunnels, int width, bool ellipsoid);
// A Y whose upper limbs (radius `limb_radius`) bend towards each other and overlap by `overlap` voxels (0: touch).
HardMask y_touch_mask(double limb_radius, double overlap);
// An ellipsoidal cell with `cavities` (1..3) empty balls inside it.
HardMask cavity_mask(int cavities);
// A demo nucleus of class `class_index` (0..5), seed `seed`, resampled to 64³ soft-edged, with `specks` specks.
HardMask soft_demo_mask(int class_index, std::uint64_t seed, int specks);
// Object `label` of a UroCell label volume (its voxels set to 255), resampled so its longest side spans 52 voxels,
// soft-edged, with `specks` specks. Empty optional when the object cannot be read.
std::optional<HardMask> soft_urocell_mask(const volume::LabelImage& volume, std::uint32_t label, const std::string& name,
                                          int specks, std::uint64_t seed);

// What the default label-volume path (describe_volume with default VolumeOptions, on the mask written as an 8-bit
// gzipped NIfTI, surfaces only) made of a mask: the table docs/accuracy.md quotes.
struct HardMaskOutcome {
  std::int64_t pieces = 0, kept = 0, specks = 0, fragments = 0;  // pieces: components before merging
  int genus = -1;
  bool ok = false;                     // the one object was meshed genus 0
  std::string repair = "none", refusal;
  double volume_change = 0;            // of the handle repair (kept or not)
};
// `decimate` false skips the last step, the quadric decimation to 10,000 vertices (OpenMesh's link condition keeps
// the genus; it is most of the time on these 64³ masks), for the sweeps; the objects, repairs and status are the same.
HardMaskOutcome default_path_outcome(const HardMask& mask, bool decimate = true);
void print_outcome_header();
void print_outcome_row(const HardMask& mask, const HardMaskOutcome& outcome);

// Every generated case but the UroCell ones (those need ../shared/data): 15 drilled balls and 15 drilled
// ellipsoids, 9 touching Ys, 3 cells with cavities, 18 soft demo cells.
std::vector<HardMask> generated_hard_masks();

}  // namespace wish::testing
