#pragma once
// Effective configuration of `wish serve`. Every limit has a flag and an environment variable (bound in
// cli/cmd_serve.cpp; flag wins over environment, environment over the default here) and is printed at start.

#include <cstdint>
#include <filesystem>
#include <string>

namespace wish::server {

struct ServerConfig {
  std::string host = "127.0.0.1";            // listen address (WISH_HOST)
  int port = 8080;                           // 0: pick a free port (logged)
  std::filesystem::path models_dir;          // *.json model files, loaded at start and on SIGHUP / admin reload
  std::string default_model = "default";     // used when a classify request names none (else: the only model)

  // Limits (413 when exceeded).
  std::uint64_t max_upload_bytes = 64ull << 20;  // whole request body
  std::int64_t max_vertices = 500'000;           // per mesh
  std::int64_t max_faces = 1'000'000;            // per mesh, after triangulation
  int max_lmax = 40;                             // SH degree a request may ask for; within core's range (finalize)
  int max_parts = 16;                            // mesh parts in one multipart request
  int max_steps = 200;                           // flow step cap a request may ask for
  // Label volume uploads (NIfTI-1, TIFF): one result per object.
  std::int64_t max_volume_voxels = 256ll * 256 * 256;  // nx * ny * nz, checked before the voxels are allocated
  std::int64_t max_volume_objects = 1'000;             // distinct objects found in one volume (before the filters)
  // Voxels of one object's padded bounding box, the memory the surface extraction allocates; an object past it is
  // refused (413 box_too_large), the others are still described.
  std::int64_t max_object_box_voxels = 64ll << 20;

  // The novelty flag's threshold quantile for every model (core/classify/novelty.hpp); 0: each model's own (0.99
  // unless it was trained with another).
  double novelty_quantile = 0;

  double time_limit_seconds = 120;   // per request, from arrival (queue wait included); 504 past it
  double volume_time_limit_seconds = 600;  // the same for a request that uploads a label volume
  int queue_size = 32;               // jobs waiting for a worker; beyond: 503 + Retry-After
  // Admission by time (work_backlog.hpp): a compute request is refused at once (503 queue_full + Retry-After, its
  // body unread) when the predicted wait for a worker plus its own predicted seconds pass this fraction of its time
  // limit, so an admitted request finishes within its limit unless the machine slows by more than the margin left:
  // 0.5 survives a halving of the speed after admission. It costs no throughput while the work admitted still keeps
  // every worker busy until refused clients come back (Retry-After). 0: off (the queue's count alone decides).
  // (0.8 left 3 of 64 requests of the 172K-vertex mesh to 504 on a machine whose load rose during the run:
  // docs/benchmarks.md.)
  double admit_fraction = 0.5;
  int workers = 0;                   // compute threads; 0: number of cores
  int http_threads = 0;              // most HTTP connection threads, started on demand, one per open connection:
                                     // the connection cap (connection_threads.hpp); 0: 1024
  double read_timeout_seconds = 30;  // a connection that sends nothing for this long (headers, or body progress)
                                     // is dropped, freeing its thread; a slow upload that keeps sending is fine
  double shutdown_grace_seconds = 30;  // SIGTERM: finish in-flight requests within this, then cancel them
  int retry_after_seconds = 1;

  // The web page (web/src: plain ES modules, no build step) served at GET /; empty: no page (GET / is 404).
  std::filesystem::path web_dir;
  // The three.js the page imports: the root of Debian's libjs-three, served under /vendor/three/ (static_assets.hpp).
  std::filesystem::path three_dir;

  std::string auth_token;            // non-empty: /v1/* requires "Authorization: Bearer <token>"
  bool json_log = false;             // one JSON object per log line
  std::string log_level = "info";    // trace, debug, info, warn, error

  // Resolves the 0 defaults (workers, http_threads) and checks ranges; throws InvalidInputError("bad_config").
  void finalize();
  // Human-readable "key = value" lines; the token is masked.
  std::string describe() const;
};

}  // namespace wish::server
