#pragma once
// Prometheus text exposition (format 0.0.4) of the service: requests by route and status, latency histograms by
// route, per-stage duration histograms, rejected requests by reason, model reloads; gauges (queue depth, busy
// workers, loaded models) are sampled by the caller at scrape time and passed to render().

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <utility>

namespace wish::server {

class Histogram {
 public:
  // Upper bounds in seconds: from a 1 ms request to the default 120 s time limit.
  static constexpr std::array<double, 15> kBounds{0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25,
                                                  0.5,   1.0,    2.5,   5.0,  10.0,  30.0, 120.0};
  void observe(double seconds);
  // Appends the _bucket / _sum / _count lines; `labels` is "" or `key="value",...` without braces.
  void render(std::string& out, const std::string& name, const std::string& labels) const;

 private:
  std::array<std::uint64_t, kBounds.size()> buckets_{};  // non-cumulative; summed when rendered
  std::uint64_t count_ = 0;
  double sum_ = 0;
};

struct Gauges {
  std::size_t queue_depth = 0, queue_capacity = 0;
  int workers = 0, busy_workers = 0;
  std::size_t models_loaded = 0;
  int in_flight_requests = 0;
};

class Metrics {
 public:
  void observe_request(const std::string& route, int status, double seconds);
  void observe_stage(const std::string& stage, double seconds);
  void count_rejected(const std::string& reason);       // queue_full, shutting_down, timeout, ...
  void count_reload(bool ok);
  std::string render(const Gauges& gauges) const;

 private:
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, int>, std::uint64_t> requests_;  // (route, status) -> count
  std::map<std::string, Histogram> latency_;                       // route -> histogram
  std::map<std::string, Histogram> stages_;                        // stage -> histogram
  std::map<std::string, std::uint64_t> rejected_;
  std::uint64_t reloads_ok_ = 0, reloads_failed_ = 0;
};

}  // namespace wish::server
