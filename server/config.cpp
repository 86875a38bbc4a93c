#include "server/config.hpp"

#include <algorithm>
#include <sstream>
#include <thread>

#include "core/classify/feature_pipeline.hpp"  // kMinFeatureLmax
#include "core/common/errors.hpp"
#include "core/sh/sh_lmax_range.hpp"

namespace wish::server {

namespace {
void require(bool ok, const std::string& what) {
  if (!ok) throw InvalidInputError("bad_config", "invalid server configuration: " + what);
}
}  // namespace

void ServerConfig::finalize() {
  if (workers <= 0) workers = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (http_threads <= 0) http_threads = std::max(1024, workers + queue_size + 8);
  require(port >= 0 && port <= 65535, "port must be in 0..65535");
  require(max_upload_bytes > 0, "max upload bytes must be > 0");
  require(max_vertices > 0 && max_faces > 0, "vertex and face limits must be > 0");
  // Core's bounds, not the service's own: a request's lmax starts at the features' minimum, and the SH fit refuses
  // anything above kShMaxFitLmax, so a larger limit would only admit requests that fail later.
  require(max_lmax >= kMinFeatureLmax && max_lmax <= kShMaxFitLmax,
          "max Lmax " + std::to_string(max_lmax) + " must be in " + std::to_string(kMinFeatureLmax) + ".." +
              std::to_string(kShMaxFitLmax) + " (the SH fit's limit is Lmax " + std::to_string(kShMaxFitLmax) + ")");
  require(max_parts >= 1, "max parts must be >= 1");
  require(max_steps >= 1, "max steps must be >= 1");
  require(time_limit_seconds > 0, "time limit must be > 0");
  require(novelty_quantile == 0 || (novelty_quantile > 0 && novelty_quantile < 1),
          "novelty quantile must be 0 (each model's own) or between 0 and 1");
  require(volume_time_limit_seconds > 0, "volume time limit must be > 0");
  require(max_volume_voxels > 0 && max_volume_objects > 0 && max_object_box_voxels > 0,
          "volume voxel, object and object box limits must be > 0");
  require(queue_size >= 0, "queue size must be >= 0");
  require(admit_fraction >= 0 && admit_fraction <= 1, "admit fraction must be in [0, 1] (0: off)");
  require(workers <= 1024 && http_threads <= 4096, "too many threads");
  require(shutdown_grace_seconds >= 0, "grace period must be >= 0");
  require(read_timeout_seconds > 0 && read_timeout_seconds <= 3600, "read timeout must be in (0, 3600] s");
  require(retry_after_seconds >= 1, "retry-after must be >= 1");
  require(!models_dir.empty(), "a models directory is required (--models / WISH_MODELS)");
}

std::string ServerConfig::describe() const {
  std::ostringstream out;
  out << "host = " << host << "\n"
      << "port = " << port << "\n"
      << "models_dir = " << models_dir.string() << "\n"
      << "default_model = " << default_model << "\n"
      << "max_upload_bytes = " << max_upload_bytes << "\n"
      << "max_vertices = " << max_vertices << "\n"
      << "max_faces = " << max_faces << "\n"
      << "max_lmax = " << max_lmax << "\n"
      << "max_parts = " << max_parts << "\n"
      << "max_steps = " << max_steps << "\n"
      << "max_volume_voxels = " << max_volume_voxels << "\n"
      << "max_volume_objects = " << max_volume_objects << "\n"
      << "max_object_box_voxels = " << max_object_box_voxels << "\n"
      << "time_limit_seconds = " << time_limit_seconds << "\n"
      << "novelty_quantile = " << novelty_quantile << (novelty_quantile == 0 ? " (each model's own)" : "") << "\n"
      << "volume_time_limit_seconds = " << volume_time_limit_seconds << "\n"
      << "queue_size = " << queue_size << "\n"
      << "admit_fraction = " << admit_fraction << (admit_fraction == 0 ? " (off: the queue's count alone)" : "")
      << "\n"
      << "workers = " << workers << "\n"
      << "http_threads = " << http_threads << "\n"
      << "read_timeout_seconds = " << read_timeout_seconds << "\n"
      << "shutdown_grace_seconds = " << shutdown_grace_seconds << "\n"
      << "retry_after_seconds = " << retry_after_seconds << "\n"
      << "web_dir = " << (web_dir.empty() ? std::string("(none: no web page)") : web_dir.string()) << "\n"
      << "three_dir = " << (three_dir.empty() ? std::string("(none)") : three_dir.string()) << "\n"
      << "auth = " << (auth_token.empty() ? "off" : "bearer token (set)") << "\n"
      << "json_log = " << (json_log ? "true" : "false") << "\n"
      << "log_level = " << log_level;
  return out.str();
}

}  // namespace wish::server
