#include "server/metrics.hpp"

#include <cstdio>

namespace wish::server {

namespace {
std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// Label values are route templates, stage names and reason codes chosen by us, but escape anyway.
std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') { out += "\\n"; continue; }
    out += c;
  }
  return out;
}

void header(std::string& out, const char* name, const char* type, const char* help) {
  out += "# HELP ";
  out += name;
  out += ' ';
  out += help;
  out += "\n# TYPE ";
  out += name;
  out += ' ';
  out += type;
  out += '\n';
}
}  // namespace

void Histogram::observe(double seconds) {
  ++count_;
  sum_ += seconds;
  for (std::size_t i = 0; i < kBounds.size(); ++i)
    if (seconds <= kBounds[i]) { ++buckets_[i]; break; }
}

void Histogram::render(std::string& out, const std::string& name, const std::string& labels) const {
  const std::string sep = labels.empty() ? "" : ",";
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i < kBounds.size(); ++i) {
    cumulative += buckets_[i];
    out += name + "_bucket{" + labels + sep + "le=\"" + number(kBounds[i]) + "\"} " + std::to_string(cumulative) + "\n";
  }
  out += name + "_bucket{" + labels + sep + "le=\"+Inf\"} " + std::to_string(count_) + "\n";
  const std::string braces = labels.empty() ? "" : "{" + labels + "}";
  out += name + "_sum" + braces + " " + number(sum_) + "\n";
  out += name + "_count" + braces + " " + std::to_string(count_) + "\n";
}

void Metrics::observe_request(const std::string& route, int status, double seconds) {
  std::lock_guard lock(mutex_);
  ++requests_[{route, status}];
  latency_[route].observe(seconds);
}

void Metrics::observe_stage(const std::string& stage, double seconds) {
  std::lock_guard lock(mutex_);
  stages_[stage].observe(seconds);
}

void Metrics::count_rejected(const std::string& reason) {
  std::lock_guard lock(mutex_);
  ++rejected_[reason];
}

void Metrics::count_reload(bool ok) {
  std::lock_guard lock(mutex_);
  ++(ok ? reloads_ok_ : reloads_failed_);
}

std::string Metrics::render(const Gauges& g) const {
  std::lock_guard lock(mutex_);
  std::string out;
  header(out, "wish_http_requests_total", "counter", "HTTP requests by route template and status.");
  for (const auto& [key, count] : requests_)
    out += "wish_http_requests_total{route=\"" + escape(key.first) + "\",status=\"" + std::to_string(key.second) +
           "\"} " + std::to_string(count) + "\n";
  header(out, "wish_http_request_duration_seconds", "histogram", "Request latency from routing to response.");
  for (const auto& [route, h] : latency_)
    h.render(out, "wish_http_request_duration_seconds", "route=\"" + escape(route) + "\"");
  header(out, "wish_stage_duration_seconds", "histogram",
         "Per-stage compute durations (queue_wait, read, validate, map, fit, classify, total).");
  for (const auto& [stage, h] : stages_) h.render(out, "wish_stage_duration_seconds", "stage=\"" + escape(stage) + "\"");
  header(out, "wish_rejected_requests_total", "counter", "Requests refused before compute, by reason.");
  for (const auto& [reason, count] : rejected_)
    out += "wish_rejected_requests_total{reason=\"" + escape(reason) + "\"} " + std::to_string(count) + "\n";
  header(out, "wish_model_reloads_total", "counter", "Model directory reloads by result.");
  out += "wish_model_reloads_total{result=\"ok\"} " + std::to_string(reloads_ok_) + "\n";
  out += "wish_model_reloads_total{result=\"partial\"} " + std::to_string(reloads_failed_) + "\n";
  header(out, "wish_queue_depth", "gauge", "Jobs waiting for a compute worker.");
  out += "wish_queue_depth " + std::to_string(g.queue_depth) + "\n";
  header(out, "wish_queue_capacity", "gauge", "Configured job queue size.");
  out += "wish_queue_capacity " + std::to_string(g.queue_capacity) + "\n";
  header(out, "wish_workers", "gauge", "Compute worker threads.");
  out += "wish_workers " + std::to_string(g.workers) + "\n";
  header(out, "wish_workers_busy", "gauge", "Compute workers running a job.");
  out += "wish_workers_busy " + std::to_string(g.busy_workers) + "\n";
  header(out, "wish_requests_in_flight", "gauge", "Compute requests accepted and not yet answered.");
  out += "wish_requests_in_flight " + std::to_string(g.in_flight_requests) + "\n";
  header(out, "wish_models_loaded", "gauge", "Classifier models currently loaded.");
  out += "wish_models_loaded " + std::to_string(g.models_loaded) + "\n";
  return out;
}

}  // namespace wish::server
