// The gateway (server/gateway.hpp) without a socket: model resolution, admission, fan-out with the deadline
// arithmetic, waiting and cancelling, the cancel registry, and batch assembly. Most tests replace the pipeline by a
// stand-in compute function that records the job it was given; one runs the real pipeline on an icosphere.

#include "server/gateway.hpp"

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/io/mesh_io.hpp"
#include "core/mesh/icosphere.hpp"
#include "tests/testing/test_data.hpp"

namespace wish::server {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// Polls `condition` every 5 ms for at most `limit`; true when it held.
template <class F>
bool wait_for(F condition, std::chrono::milliseconds limit = 5000ms) {
  const auto end = Clock::now() + limit;
  while (Clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(5ms);
  }
  return condition();
}

nlohmann::json body_of(const ApiResponse& r) { return nlohmann::json::parse(r.body); }

// A models directory with the bundled default model, or an empty one.
struct ModelDir {
  std::filesystem::path path;
  explicit ModelDir(bool with_default) {
    path = std::filesystem::temp_directory_path() /
           ("wish-gateway-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    std::filesystem::create_directories(path);
    if (with_default)
      std::filesystem::copy_file(testing::project_data_dir() / "models" / "default.json", path / "default.json");
  }
  ~ModelDir() { std::filesystem::remove_all(path); }
  static int& counter() { static int n = 0; return n; }
};

// Records every job the gateway hands out; returns `reply(job)`.
struct RecordingCompute {
  std::mutex mutex;
  std::vector<ComputeJob> jobs;
  std::function<ComputeOutcome(const ComputeJob&)> reply = [](const ComputeJob& job) {
    ComputeOutcome o;
    o.status = 200;
    o.result = {{"bytes", job.part.bytes->size()}};
    o.vertices = 10;
    o.faces = 16;
    return o;
  };
  Gateway::ComputeFunction function() {
    return [this](const ComputeJob& job, const ServerConfig&) {
      {
        std::lock_guard lock(mutex);
        jobs.push_back(job);
      }
      return reply(job);
    };
  }
  std::size_t count() {
    std::lock_guard lock(mutex);
    return jobs.size();
  }
};

struct Fixture {
  // Declared so that the pool (whose jobs call `compute`) is destroyed before `compute`.
  ServerConfig config;
  ModelDir dir;
  ModelRegistry models;
  Metrics metrics;
  CancelRegistry cancels;
  RecordingCompute compute;
  WorkerPool pool;
  Gateway gateway;

  explicit Fixture(bool with_model = false, int workers = 2, int queue = 8, double time_limit = 60)
      : config(make_config(time_limit)), dir(with_model), models(dir.path, "default"), pool(workers, queue),
        gateway(config, models, pool, metrics, cancels, compute.function()) {
    models.reload();
  }
  static ServerConfig make_config(double time_limit) {
    ServerConfig c;
    c.time_limit_seconds = time_limit;
    c.workers = 2;
    c.models_dir = "(the registry is given its directory itself)";
    c.finalize();
    return c;
  }
};

ComputeRequest raw_request(Operation op, std::string body, ParamMap params = {}) {
  ComputeRequest r;
  r.op = op;
  r.request_id = "req-1";
  r.body = std::move(body);
  r.content_type = "application/octet-stream";
  r.params = std::move(params);
  return r;
}

ComputeRequest multipart_request(Operation op, std::vector<FormPart> form) {
  ComputeRequest r;
  r.op = op;
  r.request_id = "req-2";
  r.multipart = true;
  r.form = std::move(form);
  return r;
}

TEST(Gateway, HealthAnswersOk) {
  Fixture f;
  const ApiResponse r = f.gateway.health();
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(body_of(r)["status"], "ok");
}

TEST(Gateway, ReadyIsRefusedWithoutModelAndWhileDraining) {
  Fixture none(false);
  ApiResponse r = none.gateway.ready("id");
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(body_of(r)["error"]["code"], "not_ready");
  ASSERT_NE(r.header("Retry-After"), nullptr);

  Fixture loaded(true);
  EXPECT_EQ(loaded.gateway.ready("id").status, 200);
  loaded.gateway.begin_drain();
  r = loaded.gateway.ready("id");
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(body_of(r)["error"]["details"]["shutting_down"], "true");
}

TEST(Gateway, MetricsAreTextExposition) {
  Fixture f;
  const ApiResponse r = f.gateway.metrics_text();
  EXPECT_EQ(r.status, 200);
  EXPECT_NE(r.content_type.find("text/plain"), std::string::npos);
  EXPECT_NE(r.body.find("wish_requests_in_flight"), std::string::npos) << r.body.substr(0, 400);
}

TEST(Gateway, RawBodyIsOneJobAndTheResultCarriesTheRequestId) {
  Fixture f;
  const ApiResponse r = f.gateway.compute(raw_request(Operation::Describe, "OFF bytes", {{"lmax", "6"}}));
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body_of(r)["request_id"], "req-1");
  EXPECT_EQ(body_of(r)["bytes"], 9);
  ASSERT_EQ(f.compute.count(), 1u);
  EXPECT_EQ(f.compute.jobs[0].params.descriptor.lmax, 6);
  EXPECT_EQ(f.compute.jobs[0].model, nullptr);  // describe takes no model
  EXPECT_EQ(r.parts, 1);
  EXPECT_EQ(r.vertices, 10);
  EXPECT_EQ(f.gateway.in_flight(), 0);
}

TEST(Gateway, BadParameterIsRefusedBeforeAnyJob) {
  Fixture f;
  const ApiResponse r = f.gateway.compute(raw_request(Operation::Describe, "x", {{"lamx", "6"}}));
  EXPECT_EQ(r.status, 400);
  EXPECT_EQ(body_of(r)["error"]["code"], "invalid_parameter");
  EXPECT_EQ(r.error_code, "invalid_parameter");
  EXPECT_EQ(f.compute.count(), 0u);
}

// The answer's status follows its parts': a one-part upload of a bad mesh fails as that part did (so `curl -f`
// sees it), every part good is 200, the same error in every part is that error's status, and parts that differ are
// 207 (see the test above). The body is the same BatchResponse in every case.
TEST(Gateway, BatchStatusIsThePartsCommonStatus) {
  Fixture f;
  f.compute.reply = [](const ComputeJob& job) {
    ComputeOutcome o;
    if (*job.part.bytes == "bad") {
      o.error = to_api_error(WishError(ErrorCategory::Unmappable, "genus_nonzero", "genus 1"));
      o.status = o.error.status;
    } else if (*job.part.bytes == "huge") {
      o.error = to_api_error(WishError(ErrorCategory::TooLarge, "limit_exceeded", "too many vertices"));
      o.status = o.error.status;
    } else {
      o.status = 200;
      o.result = {{"content", *job.part.bytes}};
    }
    return o;
  };
  const auto run = [&](std::vector<std::string> contents) {
    std::vector<FormPart> form;
    for (std::size_t i = 0; i < contents.size(); ++i)
      form.push_back({"mesh", "m" + std::to_string(i) + ".off", "", contents[i]});
    return f.gateway.compute(multipart_request(Operation::Describe, std::move(form)));
  };
  ApiResponse r = run({"bad"});
  EXPECT_EQ(r.status, 422) << r.body;
  auto body = body_of(r);
  ASSERT_EQ(body["results"].size(), 1u);
  EXPECT_EQ(body["results"][0]["status"], 422);
  EXPECT_EQ(body["results"][0]["error"]["code"], "genus_nonzero");
  EXPECT_EQ(body["error"]["code"], "genus_nonzero");  // the top-level error every 4xx answer carries
  EXPECT_EQ(r.error_code, "genus_nonzero");

  r = run({"good"});
  EXPECT_EQ(r.status, 200) << r.body;
  EXPECT_FALSE(body_of(r).contains("error"));

  r = run({"good", "good"});
  EXPECT_EQ(r.status, 200) << r.body;

  r = run({"bad", "bad"});
  EXPECT_EQ(r.status, 422) << r.body;

  r = run({"huge"});
  EXPECT_EQ(r.status, 413) << r.body;
  EXPECT_EQ(body_of(r)["error"]["code"], "limit_exceeded");

  r = run({"bad", "huge"});  // two different errors: still Multi-Status
  EXPECT_EQ(r.status, 207) << r.body;
  body = body_of(r);
  EXPECT_EQ(body["results"][0]["status"], 422);
  EXPECT_EQ(body["results"][1]["status"], 413);
}

TEST(Gateway, BatchStatusRule) {
  EXPECT_EQ(batch_status({}), 200);
  EXPECT_EQ(batch_status({200}), 200);
  EXPECT_EQ(batch_status({422}), 422);
  EXPECT_EQ(batch_status({200, 200, 200}), 200);
  EXPECT_EQ(batch_status({504, 504}), 504);
  EXPECT_EQ(batch_status({200, 422}), 207);
  EXPECT_EQ(batch_status({422, 200}), 207);
  EXPECT_EQ(batch_status({422, 413}), 207);
}

// A label volume's outcome carries its VolumeResult whatever its status (compute_service.cpp sets the status from
// its objects'): raw, the answer has that status and the result, with the first refusal at the top level when it
// is an error; as a multipart part, the item keeps its result beside its status (and its error when >= 400).
TEST(Gateway, VolumeOutcomeKeepsItsObjectsWhateverItsStatus) {
  Fixture f;
  f.compute.reply = [](const ComputeJob& job) {
    ComputeOutcome o;
    o.status = *job.part.bytes == "mixed" ? 207 : 422;
    o.error = to_api_error(WishError(ErrorCategory::Unmappable, "genus_nonzero", "genus 1"));
    o.result = {{"objects", nlohmann::json::array({{{"label_id", 1}, {"status", o.status == 207 ? 200 : 422}},
                                                   {{"label_id", 2}, {"status", 422}}})}};
    return o;
  };
  ApiResponse r = f.gateway.compute(raw_request(Operation::Describe, "mixed"));
  EXPECT_EQ(r.status, 207) << r.body;
  auto body = body_of(r);
  EXPECT_EQ(body["objects"].size(), 2u);
  EXPECT_EQ(body["request_id"], "req-1");
  EXPECT_FALSE(body.contains("error"));  // a 207 is not an error answer
  EXPECT_EQ(r.error_code, "genus_nonzero");  // the access line still names the first refusal

  r = f.gateway.compute(raw_request(Operation::Describe, "refused"));
  EXPECT_EQ(r.status, 422) << r.body;
  body = body_of(r);
  EXPECT_EQ(body["objects"].size(), 2u);
  EXPECT_EQ(body["error"]["code"], "genus_nonzero");

  std::vector<FormPart> form{{"mesh", "a.nii", "", "mixed"}, {"mesh", "b.nii", "", "refused"}};
  r = f.gateway.compute(multipart_request(Operation::Describe, std::move(form)));
  EXPECT_EQ(r.status, 207) << r.body;
  body = body_of(r);
  EXPECT_EQ(body["results"][0]["status"], 207);
  EXPECT_EQ(body["results"][0]["result"]["objects"].size(), 2u);
  EXPECT_FALSE(body["results"][0].contains("error"));
  EXPECT_EQ(body["results"][1]["status"], 422);
  EXPECT_EQ(body["results"][1]["result"]["objects"].size(), 2u);
  EXPECT_EQ(body["results"][1]["error"]["code"], "genus_nonzero");
  EXPECT_FALSE(body.contains("error"));
}

TEST(Gateway, BatchAnswersOneEntryPerPartInOrder) {
  Fixture f;
  f.compute.reply = [](const ComputeJob& job) {
    ComputeOutcome o;
    if (*job.part.bytes == "bad") {
      o.error = to_api_error(WishError(ErrorCategory::Unmappable, "genus_nonzero", "genus 1"));
      o.status = o.error.status;
    } else {
      o.status = 200;
      o.result = {{"content", *job.part.bytes}};
      o.vertices = 100;
      o.faces = 196;
    }
    return o;
  };
  const ApiResponse r = f.gateway.compute(multipart_request(
      Operation::Describe, {{"mesh1", "a.off", "", "good"}, {"lmax", "", "", "5"}, {"mesh2", "b.off", "", "bad"},
                            {"file3", "", "", "good2"}}));
  ASSERT_EQ(r.status, 207) << r.body;  // the parts differ: Multi-Status
  const auto body = body_of(r);
  EXPECT_FALSE(body.contains("error"));  // a 207 is not an error answer
  EXPECT_EQ(body["request_id"], "req-2");
  ASSERT_EQ(body["results"].size(), 3u);
  EXPECT_EQ(body["results"][0]["part"], "mesh1");
  EXPECT_EQ(body["results"][0]["filename"], "a.off");
  EXPECT_EQ(body["results"][0]["status"], 200);
  EXPECT_EQ(body["results"][0]["result"]["content"], "good");
  EXPECT_EQ(body["results"][0]["result"]["request_id"], "req-2");
  EXPECT_EQ(body["results"][1]["status"], 422);
  EXPECT_EQ(body["results"][1]["error"]["code"], "genus_nonzero");
  EXPECT_EQ(body["results"][2]["part"], "file3");
  EXPECT_FALSE(body["results"][2].contains("filename"));
  EXPECT_EQ(r.error_code, "genus_nonzero");
  EXPECT_EQ(r.parts, 3);
  EXPECT_EQ(r.vertices, 200);  // summed over the parts that were read
  EXPECT_EQ(r.faces, 392);
  // The form field "lmax" is a parameter, given to every job.
  ASSERT_EQ(f.compute.count(), 3u);
  for (const auto& job : f.compute.jobs) EXPECT_EQ(job.params.descriptor.lmax, 5);
}

// A request that reaches compute while draining was sent before the listener closed: it is computed. Only past
// the grace period is it refused.
TEST(Gateway, DrainingComputesAndPastTheGraceRefusesWith503AndRetryAfter) {
  Fixture f;
  f.gateway.begin_drain();
  ApiResponse r = f.gateway.compute(raw_request(Operation::Describe, "x"));
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(f.compute.count(), 1u);

  f.gateway.end_grace();
  r = f.gateway.compute(raw_request(Operation::Describe, "x"));
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(body_of(r)["error"]["code"], "shutting_down");
  EXPECT_NE(r.header("Retry-After"), nullptr);
  EXPECT_EQ(f.compute.count(), 1u);
}

TEST(Gateway, ClassifyResolvesTheModel) {
  Fixture none(false);
  ApiResponse r = none.gateway.compute(raw_request(Operation::Classify, "x"));
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(body_of(r)["error"]["code"], "no_model_loaded");

  Fixture f(true);
  r = f.gateway.compute(raw_request(Operation::Classify, "x", {{"model", "nope"}}));
  EXPECT_EQ(r.status, 404);
  EXPECT_EQ(body_of(r)["error"]["code"], "model_not_found");
  EXPECT_EQ(body_of(r)["error"]["details"]["model"], "nope");

  r = f.gateway.compute(raw_request(Operation::Classify, "x"));
  ASSERT_EQ(r.status, 200) << r.body;
  ASSERT_EQ(f.compute.count(), 1u);
  ASSERT_NE(f.compute.jobs[0].model, nullptr);
  const std::string name = f.models.default_name();  // the only model loaded, whatever its name
  ASSERT_FALSE(name.empty());
  EXPECT_EQ(model_name(*f.compute.jobs[0].model), name);

  // An explicit descriptor setting that differs from the model's is refused, never silently computed.
  r = f.gateway.compute(raw_request(Operation::Classify, "x", {{"lmax", "3"}}));
  EXPECT_EQ(r.status, 400);
  EXPECT_EQ(body_of(r)["error"]["code"], "descriptor_mismatch");
  EXPECT_EQ(f.compute.count(), 1u);

  EXPECT_EQ(f.gateway.model(name, "id").status, 200);
  EXPECT_EQ(body_of(f.gateway.model(name, "id"))["is_default"], true);
  EXPECT_EQ(f.gateway.model("nope", "id").status, 404);
}

TEST(Gateway, FullQueueIsRefusedAtOnceWithNoJobQueued) {
  Fixture f(false, /*workers=*/1, /*queue=*/0);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  // Capacity 0 takes a job only when a worker is idle, which it is once its thread has started.
  ASSERT_TRUE(wait_for([&] { return f.pool.try_submit({[released] { released.wait(); }}); }));
  ASSERT_TRUE(wait_for([&] { return f.pool.busy_workers() == 1; }));
  const ApiResponse r = f.gateway.compute(raw_request(Operation::Describe, "x"));
  release.set_value();
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(body_of(r)["error"]["code"], "queue_full");
  EXPECT_EQ(f.compute.count(), 0u);
  EXPECT_NE(f.metrics.render({}).find("reason=\"queue_full\""), std::string::npos);
}

TEST(Gateway, AdmissionRefusesAnOversizedContentLengthBeforeTheBody) {
  Fixture f(false, /*workers=*/1, /*queue=*/0);
  AdmissionQuery query;
  query.content_length = f.config.max_upload_bytes + 1;
  const AdmissionVerdict v = f.gateway.admit(query, "req-413");
  ASSERT_FALSE(v.admitted());
  EXPECT_EQ(v.refusal.status, 413);
  EXPECT_EQ(body_of(v.refusal)["error"]["code"], "payload_too_large");
  EXPECT_EQ(body_of(v.refusal)["error"]["details"]["limit"], f.config.max_upload_bytes);
  EXPECT_TRUE(wait_for([&] { return f.pool.accepting(); }));  // no place was taken
}

TEST(Gateway, AnAdmittedRequestHoldsItsQueuePlaceUntilItsJobIsQueued) {
  Fixture f(false, /*workers=*/1, /*queue=*/0);
  ASSERT_TRUE(wait_for([&] { return f.pool.accepting(); }));  // the worker's thread is up
  AdmissionQuery query;
  query.content_length = 1;
  AdmissionVerdict first = f.gateway.admit(query, "req-a");
  ASSERT_TRUE(first.admitted());
  // Its body is being read: the only place is taken, the next request is refused at once.
  const AdmissionVerdict second = f.gateway.admit(query, "req-b");
  ASSERT_FALSE(second.admitted());
  EXPECT_EQ(second.refusal.status, 503);
  EXPECT_EQ(body_of(second.refusal)["error"]["code"], "queue_full");
  bool retry_after = false;
  for (const auto& [name, value] : second.refusal.headers) retry_after = retry_after || name == "Retry-After";
  EXPECT_TRUE(retry_after);
  // The first one's job takes the held place.
  ComputeRequest request = raw_request(Operation::Describe, "x");
  request.admission = std::move(first.admission);
  EXPECT_EQ(f.gateway.compute(std::move(request)).status, 200);
  // An admission dropped unused (its body could not be read) frees its place too.
  ASSERT_TRUE(wait_for([&] { return f.pool.accepting(); }));
  {
    const AdmissionVerdict dropped = f.gateway.admit(query, "req-c");
    ASSERT_TRUE(dropped.admitted());
  }
  EXPECT_TRUE(f.gateway.admit(query, "req-d").admitted());
}

TEST(Gateway, AdmissionRefusesARequestPredictedToEndPastItsTimeLimit) {
  Fixture f(false, /*workers=*/1, /*queue=*/8, /*time_limit=*/1.0);
  f.config.admit_fraction = 0.5;  // admitted when predicted to end within 0.5 s of arrival
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<bool> block{false};
  f.compute.reply = [&](const ComputeJob&) {
    if (block) released.wait();
    else std::this_thread::sleep_for(100ms);
    ComputeOutcome o;
    o.status = 200;
    o.result = nlohmann::json::object();
    return o;
  };
  // Learned: 1 MB in about 0.1 s, so 4 MB is predicted at about 0.1 × 4^1.25 = 0.57 s.
  EXPECT_EQ(f.gateway.compute(raw_request(Operation::Describe, std::string(1'000'000, 'x'))).status, 200);
  block = true;
  std::thread running([&] { f.gateway.compute(raw_request(Operation::Describe, std::string(4'000'000, 'x'))); });
  ASSERT_TRUE(wait_for([&] { return f.pool.busy_workers() == 1; }));
  AdmissionQuery query;
  query.content_length = 4'000'000;
  const AdmissionVerdict late = f.gateway.admit(query, "req-late");
  release.set_value();
  running.join();
  ASSERT_FALSE(late.admitted());
  EXPECT_EQ(late.refusal.status, 503);
  const auto error = body_of(late.refusal)["error"];
  EXPECT_EQ(error["code"], "queue_full");
  EXPECT_GT(error["details"]["predicted_wait_seconds"].get<double>(), 0.0);
  EXPECT_GT(error["details"]["predicted_seconds"].get<double>(), 0.3);
  EXPECT_NE(f.metrics.render({}).find("reason=\"queue_time\""), std::string::npos);
  // With the worker free, the same request is admitted although it alone is predicted past 0.5 s: that is the time
  // limit's business, not overload's.
  ASSERT_TRUE(wait_for([&] { return f.pool.busy_workers() == 0; }));
  EXPECT_TRUE(f.gateway.admit(query, "req-alone").admitted());
  // Off: the queue's count alone decides.
  f.config.admit_fraction = 0;
  EXPECT_TRUE(f.gateway.admit(query, "req-off").admitted());
}

TEST(Gateway, DeadlineCountsFromArrival) {
  Fixture f(false, 2, 8, /*time_limit=*/1.0);
  std::atomic<int> expired{-1};
  f.compute.reply = [&](const ComputeJob& job) {
    expired = job.deadline.expired() ? 1 : 0;
    ComputeOutcome o;
    o.status = 200;
    o.result = nlohmann::json::object();
    return o;
  };
  ComputeRequest fresh = raw_request(Operation::Describe, "x");
  fresh.arrival = Clock::now();
  f.gateway.compute(std::move(fresh));
  EXPECT_EQ(expired.load(), 0);

  // Arrived 2 s ago with a 1 s limit (a slow upload): the job's deadline has already passed when it starts.
  // (The gateway's own wait ends at arrival + limit + 1 s, i.e. now: it may answer 504 before the job ran, so the
  // test waits for the job itself.)
  expired = -1;
  ComputeRequest old = raw_request(Operation::Describe, "x");
  old.arrival = Clock::now() - 2s;
  f.gateway.compute(std::move(old));
  ASSERT_TRUE(wait_for([&] { return expired.load() != -1; }));
  EXPECT_EQ(expired.load(), 1);
}

TEST(Gateway, JobPastTheLimitIsAnswered504AndCancelled) {
  Fixture f(false, 1, 8, /*time_limit=*/0.2);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::promise<std::string> seen;
  f.compute.reply = [&, released](const ComputeJob& job) {
    released.wait();  // a computation that never reaches a deadline check in time
    std::string code = "none";
    try {
      job.deadline.check("test");
    } catch (const WishError& e) {
      code = e.code();
    }
    seen.set_value(code);
    return ComputeOutcome{};
  };
  const auto start = Clock::now();
  const ApiResponse r = f.gateway.compute(raw_request(Operation::Describe, "x"));
  const double waited = std::chrono::duration<double>(Clock::now() - start).count();
  EXPECT_EQ(r.status, 504);
  EXPECT_EQ(body_of(r)["error"]["code"], "timeout");
  EXPECT_GE(waited, 0.2);  // the limit, plus the second of grace for the last step
  EXPECT_EQ(f.cancels.size(), 0u);
  release.set_value();
  auto code = seen.get_future();
  ASSERT_EQ(code.wait_for(5s), std::future_status::ready);
  EXPECT_EQ(code.get(), "cancelled");  // the gateway raised the job's cancel flag when it gave up
}

TEST(Gateway, CancelRegistryStopsWaitingRequests) {
  Fixture f(false, 1, 8);
  f.compute.reply = [](const ComputeJob& job) {
    ComputeOutcome o;
    // A computation that checks its deadline every 5 ms, for at most 10 s.
    const auto end = Clock::now() + 10s;
    try {
      while (Clock::now() < end) {
        job.deadline.check("flow");
        std::this_thread::sleep_for(5ms);
      }
      o.status = 200;
      o.result = nlohmann::json::object();
    } catch (...) {
      o.error = to_api_error(std::current_exception());
      o.status = o.error.status;
    }
    return o;
  };
  auto answer = std::async(std::launch::async, [&] { return f.gateway.compute(raw_request(Operation::Describe, "x")); });
  ASSERT_TRUE(wait_for([&] { return f.cancels.size() == 1 && f.compute.count() == 1; }));
  EXPECT_EQ(f.gateway.in_flight(), 1);
  f.cancels.cancel_all();
  ASSERT_EQ(answer.wait_for(5s), std::future_status::ready);
  const ApiResponse r = answer.get();
  EXPECT_EQ(r.status, 503);
  EXPECT_EQ(body_of(r)["error"]["code"], "cancelled");
  EXPECT_EQ(f.cancels.size(), 0u);
  EXPECT_EQ(f.gateway.in_flight(), 0);
}

TEST(GatewayPipeline, DescribesAnIcosphereThroughTheRealPipeline) {
  ServerConfig config;
  config.workers = 1;
  config.models_dir = "(unused)";
  config.finalize();
  ModelDir dir(false);
  ModelRegistry models(dir.path, "default");
  WorkerPool pool(1, 4);
  Metrics metrics;
  CancelRegistry cancels;
  Gateway gateway(config, models, pool, metrics, cancels);
  const std::string off = write_mesh(make_icosphere(2), MeshFormat::Off);
  const ApiResponse r = gateway.compute(raw_request(Operation::Describe, off, {{"lmax", "4"}}));
  ASSERT_EQ(r.status, 200) << r.body;
  const auto body = body_of(r);
  EXPECT_EQ(body["descriptor"]["lmax"], 4);
  EXPECT_EQ(body["descriptor"]["invariants"].size(), 5u);
  EXPECT_EQ(r.vertices, 162);
  EXPECT_EQ(r.faces, 320);
}

}  // namespace
}  // namespace wish::server
