#include "core/pipeline/volume_pipeline.hpp"

#include <chrono>

namespace wish {

VolumeSummary for_each_object_surface(std::string_view bytes, const VolumeOptions& options,
                                      const ObjectCallback& on_object, const SummaryCallback& on_summary,
                                      const VolumeCompleteCallback& on_complete) {
  using Clock = std::chrono::steady_clock;
  VolumeSummary s;
  auto t0 = Clock::now();
  const VolumeReadResult read = read_volume(bytes, options.read);
  s.read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  s.format = read.format;
  s.datatype = read.datatype;
  s.dims = read.image.dims;
  s.spacing = read.image.spacing;
  s.unit = read.image.unit;
  s.notes = read.notes;
  t0 = Clock::now();
  const volume::ObjectSet objects = volume::find_objects(read.image, options.objects);
  s.objects_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  s.mode = objects.mode;
  s.input = objects.input;
  s.found = objects.found;
  s.kept = static_cast<std::int64_t>(objects.objects.size());
  s.dropped_not_selected = objects.dropped_not_selected;
  s.dropped_small = objects.dropped_small;
  s.dropped_truncated = objects.dropped_truncated;
  s.dropped_specks = objects.dropped_specks;
  s.fragments_merged = objects.fragments_merged;
  s.specks = objects.specks;
  s.dropped = objects.dropped;
  if (on_summary) on_summary(s);
  for (std::size_t i = 0; i < objects.objects.size(); ++i) {
    volume::ObjectSurface surface = volume::object_surface(read.image, objects, objects.objects[i], options.surface);
    on_object(i, objects.objects[i], surface);
  }
  if (on_complete) on_complete(read, objects);
  return s;
}

}  // namespace wish
