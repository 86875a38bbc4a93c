#include "core/pipeline/volume_description.hpp"

#include "core/common/error_codes.hpp"

namespace wish {

namespace {

SurfaceFigures figures_of(const volume::ObjectSurface& s) {
  SurfaceFigures f;
  f.genus = s.genus;
  f.repair = s.repair;
  f.repaired = s.repaired;
  f.repairs = s.repairs;
  f.vertices = s.mesh.vertex_count();
  f.faces = s.mesh.face_count();
  f.vertices_before_decimation = s.vertices_before_decimation;
  f.area = s.area;
  f.volume = s.volume;
  f.voxel_volume = s.voxel_volume;
  f.raw_area = s.raw_area;
  f.timings = s.timings;
  return f;
}

bool ends_the_volume(const WishError& e) { return e.category() == ErrorCategory::Timeout || e.code() == "cancelled"; }

}  // namespace

WishError surface_refusal_error(const volume::VolumeObject& object, const volume::ObjectSurface& surface) {
  const ErrorCodeInfo* info = find_error_code(surface.refusal_code);
  const ErrorCategory category = info && info->category ? *info->category : ErrorCategory::Unmappable;
  return WishError(category, surface.refusal_code, surface.refusal,
                   {{"label_id", std::int64_t{object.id}}, {"genus", std::int64_t{surface.genus}}});
}

WishError no_objects_error(const VolumeSummary& s) {
  const std::string why = s.found == 0 ? "every voxel is background (0)"
                                       : std::to_string(s.found) + " found, dropped: " +
                                             std::to_string(s.dropped_not_selected) + " not in labels, " +
                                             std::to_string(s.dropped_specks) + " specks (min_voxels overrides), " +
                                             std::to_string(s.dropped_small) + " under min_voxels, " +
                                             std::to_string(s.dropped_truncated) + " truncated (drop_truncated)";
  return WishError(ErrorCategory::Unmappable, "no_objects", "the label volume has no object to describe: " + why,
                   {{"objects_found", s.found}, {"not_selected", s.dropped_not_selected},
                    {"specks", s.dropped_specks}, {"small", s.dropped_small}, {"truncated", s.dropped_truncated}});
}

VolumeSummary describe_volume(std::string_view bytes, const VolumeOptions& options, const ObjectWork& work,
                              const ObjectResultCallback& on_object, const Deadline& deadline,
                              const SummaryCallback& on_summary, const VolumeCompleteCallback& on_complete) {
  std::int64_t kept = 0;
  return for_each_object_surface(
      bytes, options,
      [&](std::size_t index, const volume::VolumeObject& object, volume::ObjectSurface& surface) {
        if (deadline.expired()) {
          try {
            deadline.check("label volume objects");
          } catch (const WishError& e) {
            if (e.code() == "cancelled") throw;  // as it is; a timeout is reported with the count below
          }
          throw TimeoutError("time limit exceeded after " + std::to_string(index) + " of " + std::to_string(kept) +
                                 " objects of the label volume",
                             {{"stage", std::string("label volume objects")},
                              {"objects_done", static_cast<std::int64_t>(index)}, {"objects", kept}});
        }
        VolumeObjectResult out{object, figures_of(surface), std::nullopt, std::nullopt};
        if (!surface.ok) {
          out.error = surface_refusal_error(object, surface);
        } else {
          try {
            out.result = work(object, std::move(surface.mesh));
          } catch (const WishError& e) {
            if (ends_the_volume(e)) throw;
            out.error = e;
          }
        }
        on_object(index, out);
      },
      [&](const VolumeSummary& s) {
        kept = s.kept;
        if (on_summary) on_summary(s);
      },
      on_complete);
}

}  // namespace wish
