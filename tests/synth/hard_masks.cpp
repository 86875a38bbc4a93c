#include "tests/synth/hard_masks.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <functional>
#include <random>

#include "core/io/volume_io.hpp"
#include "core/pipeline/volume_description.hpp"
#include "core/synth/nucleus_shape.hpp"

namespace wish::testing {
namespace {

constexpr int N = kHardMaskSize;
constexpr double kCentre = 0.5 * (N - 1);

volume::LabelImage empty_mask() {
  volume::LabelImage image;
  image.dims = {N, N, N};
  image.unit = "um";
  image.labels.assign(static_cast<std::size_t>(N) * N * N, 0);
  return image;
}

// 255 where `inside(x, y, z)` holds (coordinates relative to the grid's centre, in voxels).
volume::LabelImage solid_mask(const std::function<bool(double, double, double)>& inside) {
  volume::LabelImage image = empty_mask();
  for (int z = 0; z < N; ++z)
    for (int y = 0; y < N; ++y)
      for (int x = 0; x < N; ++x)
        if (inside(x - kCentre, y - kCentre, z - kCentre)) image.labels[image.index(x, y, z)] = 255;
  return image;
}

double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// Trilinear interpolation of `fine` (dims fx³, values 0..255) at fractional coordinates; 0 outside.
double trilinear(const std::vector<std::uint8_t>& fine, const std::array<int, 3>& dims, double x, double y, double z) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y)), z0 = static_cast<int>(std::floor(z));
  const double fx = x - x0, fy = y - y0, fz = z - z0;
  double v = 0;
  for (int c = 0; c < 8; ++c) {
    const int xi = x0 + (c & 1), yi = y0 + (c >> 1 & 1), zi = z0 + (c >> 2 & 1);
    if (xi < 0 || yi < 0 || zi < 0 || xi >= dims[0] || yi >= dims[1] || zi >= dims[2]) continue;
    const double w = ((c & 1) ? fx : 1 - fx) * ((c >> 1 & 1) ? fy : 1 - fy) * ((c >> 2 & 1) ? fz : 1 - fz);
    v += w * fine[static_cast<std::size_t>(xi) + static_cast<std::size_t>(dims[0]) * (yi + static_cast<std::size_t>(dims[1]) * zi)];
  }
  return v;
}

// Output voxel i of the 64³ mask samples the fine grid at centre + (i - 31.5) / scale (all three axes).
volume::LabelImage resample(const std::vector<std::uint8_t>& fine, const std::array<int, 3>& dims,
                            const Eigen::Vector3d& centre, double scale) {
  volume::LabelImage image = empty_mask();
  for (int z = 0; z < N; ++z)
    for (int y = 0; y < N; ++y)
      for (int x = 0; x < N; ++x) {
        const double v = trilinear(fine, dims, centre(0) + (x - kCentre) / scale, centre(1) + (y - kCentre) / scale,
                                   centre(2) + (z - kCentre) / scale);
        image.labels[image.index(x, y, z)] = static_cast<std::uint32_t>(std::lround(std::clamp(v, 0.0, 255.0)));
      }
  return image;
}

// Specks as a threshold leaves them: clusters of 1–3 voxels above the threshold, most far from the cell (more than 6
// voxels from any voxel at or above half the maximum) and one in four within 2–3 voxels of it.
void add_specks(volume::LabelImage& image, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> coord(1, N - 2), size(1, 3), value(140, 255);
  auto distance_to_cell = [&](int x, int y, int z, int reach) {
    int best = reach + 1;
    for (int c = std::max(0, z - reach); c <= std::min(N - 1, z + reach); ++c)
      for (int b = std::max(0, y - reach); b <= std::min(N - 1, y + reach); ++b)
        for (int a = std::max(0, x - reach); a <= std::min(N - 1, x + reach); ++a)
          if (image.labels[image.index(a, b, c)] >= 128) best = std::min(best, std::max({std::abs(a - x), std::abs(b - y), std::abs(c - z)}));
    return best;
  };
  for (int placed = 0, tries = 0; placed < count && tries < 100000; ++tries) {
    const int x = coord(rng), y = coord(rng), z = coord(rng);
    const bool near = placed % 4 == 3;
    const int d = distance_to_cell(x, y, z, 7);
    if (near ? (d < 3 || d > 4) : d <= 7) continue;
    const int n = size(rng);
    for (int k = 0; k < n && x + k < N - 1; ++k) image.labels[image.index(x + k, y, z)] = static_cast<std::uint32_t>(value(rng));
    ++placed;
  }
}

}  // namespace

HardMask drilled_mask(int tunnels, int width, bool ellipsoid) {
  const Eigen::Vector3d axes = ellipsoid ? Eigen::Vector3d(26, 20, 16) : Eigen::Vector3d(22, 22, 22);
  const int off = ellipsoid ? 6 : 8;
  const int lo = -(width - 1) / 2, hi = width / 2;
  const int at[4][2] = {{-off, -off}, {off, -off}, {-off, off}, {off, off}};
  HardMask m;
  m.family = "drilled";
  m.name = std::string(ellipsoid ? "ellipsoid" : "ball") + "_tunnels" + std::to_string(tunnels) + "_width" + std::to_string(width);
  m.expected_genus = tunnels;
  m.image = solid_mask([&](double x, double y, double z) {
    if (Eigen::Vector3d(x, y, z).cwiseQuotient(axes).squaredNorm() > 1) return false;
    const int ix = static_cast<int>(std::lround(x + 0.5)), iy = static_cast<int>(std::lround(y + 0.5)),
              iz = static_cast<int>(std::lround(z + 0.5));  // x - 31.5 + 0.5 = index - 31
    for (int t = 0; t < tunnels; ++t) {
      if (t < 4 && iy - at[t][0] >= lo && iy - at[t][0] <= hi && iz - at[t][1] >= lo && iz - at[t][1] <= hi) return false;
      if (t == 4 && ix >= lo && ix <= hi && iz >= lo && iz <= hi) return false;
    }
    return true;
  });
  return m;
}

HardMask y_touch_mask(double r, double overlap) {
  // Stem along z; at the fork two limbs go out and up, then bend back so their rounded tips meet above the fork.
  const Eigen::Vector3d base(0, 0, -26), fork(0, 0, -4), left_elbow(-16, 0, 10), right_elbow(16, 0, 10);
  const double half = r - 0.5 * overlap;  // tip centres 2r - overlap apart
  const Eigen::Vector3d left_tip(-half, 0, 22), right_tip(half, 0, 22);
  HardMask m;
  m.family = "y_touch";
  char name[64];
  std::snprintf(name, sizeof name, "y_r%.1f_overlap%.1f", r, overlap);
  m.name = name;
  m.image = solid_mask([&](double x, double y, double z) {
    const Eigen::Vector3d p(x + 0.3, y + 0.2, z);
    return segment_distance(p, base, fork) <= r + 1 || segment_distance(p, fork, left_elbow) <= r ||
           segment_distance(p, fork, right_elbow) <= r || segment_distance(p, left_elbow, left_tip) <= r ||
           segment_distance(p, right_elbow, right_tip) <= r;
  });
  return m;
}

HardMask cavity_mask(int cavities) {
  const Eigen::Vector3d holes[3] = {{-9, 0, 0}, {9, 1, 0}, {0, 8, 4}};
  HardMask m;
  m.family = "cavities";
  m.name = "cell_cavities" + std::to_string(cavities);
  m.expected_genus = 0;
  m.image = solid_mask([&](double x, double y, double z) {
    const Eigen::Vector3d p(x, y, z);
    if (p.cwiseQuotient(Eigen::Vector3d(25, 20, 16)).squaredNorm() > 1) return false;
    for (int k = 0; k < cavities; ++k)
      if ((p - holes[k]).norm() <= 4) return false;
    return true;
  });
  return m;
}

HardMask soft_demo_mask(int class_index, std::uint64_t seed, int specks) {
  const synth::NucleusShape shape = synth::sample_nucleus_shape(class_index, seed);
  // The shape sampled on a fine grid (1.5 fine voxels per output voxel), its bounding sphere spanning 56 output voxels.
  const int fine_n = 96;
  const double radius = shape.bounding_radius();
  const double fine_step = 2 * radius / (fine_n - 8);  // µm per fine voxel
  std::vector<std::uint8_t> fine(static_cast<std::size_t>(fine_n) * fine_n * fine_n, 0);
  const double half = 0.5 * (fine_n - 1);
  for (int z = 0; z < fine_n; ++z)
    for (int y = 0; y < fine_n; ++y)
      for (int x = 0; x < fine_n; ++x) {
        const Eigen::Vector3d offset = fine_step * Eigen::Vector3d(x - half, y - half, z - half);
        if (offset.norm() <= radius && shape.inside(shape.centre + offset))
          fine[static_cast<std::size_t>(x) + static_cast<std::size_t>(fine_n) * (y + static_cast<std::size_t>(fine_n) * z)] = 255;
      }
  HardMask m;
  m.family = "soft_demo";
  m.name = synth::demo_classes()[static_cast<std::size_t>(class_index)] + "_" + std::to_string(seed);
  m.image = resample(fine, {fine_n, fine_n, fine_n}, Eigen::Vector3d(half, half, half), 1.0 / 1.5);
  const double voxel = fine_step * 1.5;
  m.image.spacing = Eigen::Vector3d(voxel, voxel, voxel);
  add_specks(m.image, specks, seed * 7919 + 13);
  return m;
}

std::optional<HardMask> soft_urocell_mask(const volume::LabelImage& volume, std::uint32_t label, const std::string& name,
                                          int specks, std::uint64_t seed) {
  std::array<std::int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX}, hi{-1, -1, -1};
  for (std::int64_t z = 0; z < volume.dims[2]; ++z)
    for (std::int64_t y = 0; y < volume.dims[1]; ++y)
      for (std::int64_t x = 0; x < volume.dims[0]; ++x)
        if (volume.at(x, y, z) == label) {
          const std::int64_t p[3] = {x, y, z};
          for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
        }
  if (hi[0] < 0) return std::nullopt;
  const std::array<int, 3> dims{static_cast<int>(hi[0] - lo[0] + 3), static_cast<int>(hi[1] - lo[1] + 3),
                                static_cast<int>(hi[2] - lo[2] + 3)};
  std::vector<std::uint8_t> crop(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], 0);
  for (int z = 1; z + 1 < dims[2]; ++z)
    for (int y = 1; y + 1 < dims[1]; ++y)
      for (int x = 1; x + 1 < dims[0]; ++x)
        if (volume.at(lo[0] + x - 1, lo[1] + y - 1, lo[2] + z - 1) == label)
          crop[static_cast<std::size_t>(x) + static_cast<std::size_t>(dims[0]) * (y + static_cast<std::size_t>(dims[1]) * z)] = 255;
  const int longest = *std::max_element(dims.begin(), dims.end());
  const double scale = 52.0 / longest;  // output voxels per input voxel (> 1: an upsampling)
  HardMask m;
  m.family = "soft_urocell";
  m.name = name;
  m.image = resample(crop, dims, Eigen::Vector3d(0.5 * (dims[0] - 1), 0.5 * (dims[1] - 1), 0.5 * (dims[2] - 1)), scale);
  m.image.spacing = volume.spacing / scale;
  m.image.unit = volume.unit;
  add_specks(m.image, specks, seed);
  return m;
}

HardMaskOutcome default_path_outcome(const HardMask& m, bool decimate) {
  const std::string bytes = write_nifti(m.image, "uint8", true);
  HardMaskOutcome out;
  VolumeOptions options;
  if (!decimate) options.surface.target_vertices = 0;
  const VolumeSummary s = describe_volume(
      bytes, options,
      [](const volume::VolumeObject&, Mesh) -> std::optional<PipelineResult> { return std::nullopt; },
      [&](std::size_t, VolumeObjectResult& r) {
        out.genus = r.surface.genus;
        out.ok = r.ok();
        if (r.surface.genus > 0) out.repair = r.surface.repaired ? r.surface.repair.method() : "refused";
        out.volume_change = r.surface.repair.volume_change();
        if (r.error) out.refusal = r.error->code() + ": " + r.error->what();
        out.fragments = static_cast<std::int64_t>(r.object.fragments.size());
      });
  out.pieces = s.found + s.fragments_merged;
  out.kept = s.kept;
  out.specks = s.dropped_specks;
  return out;
}

void print_outcome_header() {
  std::printf("| family | mask | pieces | specks dropped | fragments merged | genus | repair | volume change | status |\n");
  std::printf("|---|---|---:|---:|---:|---:|---|---:|---|\n");
}

void print_outcome_row(const HardMask& m, const HardMaskOutcome& o) {
  std::printf("| %s | %s | %lld | %lld | %lld | %d | %s | %.2f %% | %s |\n", m.family.c_str(), m.name.c_str(),
              static_cast<long long>(o.pieces), static_cast<long long>(o.specks), static_cast<long long>(o.fragments),
              o.genus, o.repair.c_str(), 100 * o.volume_change, o.ok ? "meshed" : o.refusal.c_str());
}

std::vector<HardMask> generated_hard_masks() {
  std::vector<HardMask> out;
  for (bool ellipsoid : {false, true})
    for (int k = 1; k <= 5; ++k)
      for (int w = 1; w <= 3; ++w) out.push_back(drilled_mask(k, w, ellipsoid));
  for (double r : {2.0, 3.0, 4.0})
    for (double overlap : {0.5, 1.0, 2.0}) out.push_back(y_touch_mask(r, overlap));
  for (int c = 1; c <= 3; ++c) out.push_back(cavity_mask(c));
  for (int cls = 0; cls < 6; ++cls)
    for (std::uint64_t seed : {11u, 12u, 13u}) out.push_back(soft_demo_mask(cls, seed, 6));
  return out;
}

}  // namespace wish::testing
