#pragma once
// The work admitted and not yet done, in predicted worker seconds, so that the gateway can refuse at once (503 +
// Retry-After, before the body is read) a request that would wait past its time limit instead of admitting it to
// answer 504 later (issue 40: 64 clients of a 172K-vertex mesh, a queue of 32, 47 answers 504).
//
// A job's seconds are predicted from its size in bytes: seconds = rate × MB^1.25. The pipeline's cost grows about as
// n^1.25 in vertices (issue 40: 10.8K / 43K / 173K / 690K vertices in 0.2 / 1.0 / 5.1 / 34 s), and bytes stand in
// for vertices because a request's Content-Length is known before its body is read. `rate` is learned from the mesh
// jobs that completed (an exponential average of their wall seconds on a worker): a machine slowed by other work
// raises it, and the admission then takes less. The backlog keeps each job's bytes, not its seconds, so the jobs
// already admitted are re-predicted at the current rate too. Before any job completed nothing is predicted (the
// queue's count alone decides). Label volumes are not predicted (their cost is per object, not per byte).
//
// The wait of a job admitted now: the workers taken in order (first in, first out) by the jobs already admitted,
// each running job for what is left of its prediction, each waiting one for its whole prediction; the wait is when
// the first worker is free after them.

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

namespace wish::server {

// Shared (std::make_shared): a ticket keeps its backlog alive, as a job can outlive the request that queued it.
class WorkBacklog : public std::enable_shared_from_this<WorkBacklog> {
 public:
  using Clock = std::chrono::steady_clock;

  // One admitted job's place in the backlog, from admission (its body perhaps still being read) until it is done;
  // it leaves the backlog when destroyed.
  class Ticket {
   public:
    ~Ticket();
    Ticket(const Ticket&) = delete;
    Ticket& operator=(const Ticket&) = delete;
    // Once the job's bytes (its part of a request) are known; none: a job whose seconds are not predicted.
    void set_bytes(std::optional<std::uint64_t> bytes);
    void start();                    // a worker took the job

   private:
    friend class WorkBacklog;
    Ticket(std::shared_ptr<WorkBacklog> backlog, std::uint64_t id) : backlog_(std::move(backlog)), id_(id) {}
    std::shared_ptr<WorkBacklog> backlog_;
    std::uint64_t id_;
  };

  explicit WorkBacklog(int workers) : workers_(workers < 1 ? 1 : workers) {}

  // Predicted worker seconds of a mesh job of `bytes`; none before a mesh job completed.
  std::optional<double> predict(std::uint64_t bytes) const;
  // A completed mesh job of `bytes` that ran `seconds` on a worker.
  void learn(std::uint64_t bytes, double seconds);
  // Seconds until a worker is free for a job admitted now.
  double wait_seconds() const;
  // Admits a job of `bytes` (none: not predicted, it counts for nothing).
  std::shared_ptr<Ticket> enter(std::optional<std::uint64_t> bytes);

  std::size_t size() const;

 private:
  struct Item {
    std::optional<std::uint64_t> bytes;
    bool running = false;
    Clock::time_point started{};
  };

  int workers_;
  mutable std::mutex mutex_;
  std::map<std::uint64_t, Item> items_;  // by admission order
  std::uint64_t next_id_ = 0;
  std::optional<double> rate_;  // seconds per MB^1.25
};

}  // namespace wish::server
