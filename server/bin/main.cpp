// `wish-server [--models DIR] --port 8080 ...`: the HTTP service (server/), also run as `wish serve ...` (the CLI
// hands its arguments over with exec, so the `wish` executable itself links no HTTP code). Every option also reads a
// WISH_* environment variable (CLI11 envname); a flag given on the command line wins over the environment.
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/common/errors.hpp"
#include "core/common/process_signals.hpp"
#include "core/sh/sh_lmax_range.hpp"
#include "server/config.hpp"
#include "server/run_server.hpp"

int main(int argc, char** argv) {
  using namespace wish;
  // The signals the service takes with sigwait must be blocked before any thread exists (process_signals.hpp).
  if (!process_signals_blocked()) {
    std::cerr << "wish-server: SIGHUP/SIGTERM/SIGINT are not blocked at start (build error: the preinit mask is missing)\n";
    return 70;
  }
  CLI::App app{"WISH HTTP service: classify / describe closed genus-0 meshes and label volumes over REST on a worker pool"};
  app.set_version_flag("--version", std::string("wish-server ") + WISH_VERSION);
  auto config = std::make_shared<server::ServerConfig>();
  auto& c = *config;
  // The options write into objects that outlive setup (the runner is called after parsing).
  auto models_dir = std::make_shared<std::string>(WISH_MODELS_DIR_DEFAULT);
  app.add_option("--models", *models_dir,
                 "Directory of *.json classifier models (reloaded on SIGHUP); default: the bundled default model")
      ->envname("WISH_MODELS")
      ->capture_default_str();
  app.add_option("--host", c.host, "Listen address")->envname("WISH_HOST")->capture_default_str();
  app.add_option("--port", c.port, "Listen port (0: any free port, logged at start)")->envname("WISH_PORT")
      ->capture_default_str();
  app.add_option("--default-model", c.default_model, "Model used when a classify request names none")
      ->envname("WISH_DEFAULT_MODEL")->capture_default_str();
  app.add_option("--max-upload-bytes", c.max_upload_bytes, "Largest request body (413 above)")
      ->envname("WISH_MAX_UPLOAD_BYTES")->capture_default_str();
  app.add_option("--max-vertices", c.max_vertices, "Most vertices per mesh (413 above)")
      ->envname("WISH_MAX_VERTICES")->capture_default_str();
  app.add_option("--max-faces", c.max_faces, "Most triangles per mesh (413 above)")
      ->envname("WISH_MAX_FACES")->capture_default_str();
  app.add_option("--max-lmax", c.max_lmax,
                 "Largest Lmax a request may ask for (413 above; at most the SH fit's " + std::to_string(kShMaxFitLmax) + ")")
      ->envname("WISH_MAX_LMAX")->capture_default_str();
  app.add_option("--max-parts", c.max_parts, "Most mesh parts in one multipart request (413 above)")
      ->envname("WISH_MAX_PARTS")->capture_default_str();
  app.add_option("--max-steps", c.max_steps, "Largest flow step cap a request may ask for (413 above)")
      ->envname("WISH_MAX_STEPS")->capture_default_str();
  app.add_option("--time-limit", c.time_limit_seconds, "Seconds per request, queue wait included (504 past it)")
      ->envname("WISH_TIME_LIMIT")->capture_default_str();
  app.add_option("--novelty-quantile", c.novelty_quantile,
                 "Quantile of a model's training novelty scores above which a prediction says novel: true "
                 "(0: each model's own, 0.99 by default)")
      ->envname("WISH_NOVELTY_QUANTILE")->capture_default_str();
  app.add_option("--max-volume-voxels", c.max_volume_voxels, "Most voxels in one uploaded label volume (413 above)")
      ->envname("WISH_MAX_VOLUME_VOXELS")->capture_default_str();
  app.add_option("--max-volume-objects", c.max_volume_objects, "Most objects in one uploaded label volume (413 above)")
      ->envname("WISH_MAX_VOLUME_OBJECTS")->capture_default_str();
  app.add_option("--max-object-box-voxels", c.max_object_box_voxels,
                 "Most voxels in one label-volume object's padded bounding box (that object: 413 box_too_large)")
      ->envname("WISH_MAX_OBJECT_BOX_VOXELS")->capture_default_str();
  app.add_option("--volume-time-limit", c.volume_time_limit_seconds,
                 "Seconds per request that uploads a label volume, queue wait included (504 past it)")
      ->envname("WISH_VOLUME_TIME_LIMIT")->capture_default_str();
  app.add_option("--queue-size", c.queue_size, "Jobs waiting for a worker (503 + Retry-After beyond)")
      ->envname("WISH_QUEUE_SIZE")->capture_default_str();
  app.add_option("--admit-fraction", c.admit_fraction,
                 "Refuse a request at once (503 + Retry-After) when its predicted queue wait plus its own predicted "
                 "seconds pass this fraction of its time limit (0: off, the queue size alone)")
      ->envname("WISH_ADMIT_FRACTION")->capture_default_str();
  app.add_option("--workers", c.workers, "Compute workers (0: number of cores)")->envname("WISH_WORKERS")
      ->capture_default_str();
  app.add_option("--http-threads", c.http_threads,
                 "Most HTTP connection threads, started on demand, one per open connection (0: 1024)")
      ->envname("WISH_HTTP_THREADS")->capture_default_str();
  app.add_option("--read-timeout", c.read_timeout_seconds,
                 "Seconds a connection may send nothing (headers or body) before it is dropped")
      ->envname("WISH_READ_TIMEOUT")->capture_default_str();
  app.add_option("--shutdown-grace", c.shutdown_grace_seconds, "Seconds to finish in-flight requests on SIGTERM")
      ->envname("WISH_SHUTDOWN_GRACE")->capture_default_str();
  app.add_option("--retry-after", c.retry_after_seconds, "Retry-After seconds sent with 503")
      ->envname("WISH_RETRY_AFTER")->capture_default_str();
  c.web_dir = WISH_WEB_DIR_DEFAULT;
  app.add_option("--web-dir", c.web_dir, "Directory of the web page served at GET / ('' for none)")
      ->envname("WISH_WEB_DIR")->capture_default_str();
  c.three_dir = WISH_THREE_DIR_DEFAULT;
  app.add_option("--three-dir", c.three_dir,
                 "Directory of the three.js the page imports (Debian's libjs-three), served under /vendor/three/")
      ->envname("WISH_THREE_DIR")->capture_default_str();
  app.add_option("--auth-token", c.auth_token, "Require 'Authorization: Bearer TOKEN' on /v1/* (prefer the env var)")
      ->envname("WISH_AUTH_TOKEN");
  app.add_flag("--json-log", c.json_log, "One JSON object per log line")->envname("WISH_JSON_LOG");
  app.add_option("--log-level", c.log_level, "trace, debug, info, warn, error")->envname("WISH_LOG_LEVEL")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}))->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    config->models_dir = *models_dir;
    return server::run_server(*config);
  } catch (const WishError& e) {
    std::cerr << "wish-server: error [" << e.code() << "]: " << e.what() << "\n";
    return 1;  // the exit statuses of `wish` (cli/command_registry.hpp): 1 refused input, 2 usage, 3 unexpected
  } catch (const std::exception& e) {
    std::cerr << "wish-server: unexpected error: " << e.what() << "\n";
    return 3;
  }
}
