#pragma once
// Compute workers behind a bounded job queue, separate from the HTTP threads: an HTTP thread parses the request,
// submits the work here and waits; when the queue is full the submit fails at once so the client gets a 503
// instead of a hang. Each worker limits OpenMP and BLAS to one thread (core/common/thread_policy.hpp) so that
// `workers` requests in parallel use `workers` cores and the machine is not oversubscribed.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace wish::server {

class WorkerPool {
 public:
  using Job = std::function<void()>;  // must not throw (compute jobs catch everything themselves)

  WorkerPool(int workers, int queue_capacity);
  ~WorkerPool();  // shutdown()
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  // One place in the queue held for a request whose body is still being read: the service admits a compute request
  // from its headers (gateway.hpp) and queues its jobs only once the body is in, and the held place counts against
  // the capacity like a queued job, so no request arriving in between can take it. Released when destroyed unused.
  class Reservation {
   public:
    Reservation() = default;
    Reservation(Reservation&& other) noexcept : pool_(other.pool_) { other.pool_ = nullptr; }
    Reservation& operator=(Reservation&& other) noexcept;
    Reservation(const Reservation&) = delete;
    Reservation& operator=(const Reservation&) = delete;
    ~Reservation() { release(); }
    explicit operator bool() const { return pool_ != nullptr; }

   private:
    friend class WorkerPool;
    explicit Reservation(WorkerPool* pool) : pool_(pool) {}
    void release();
    WorkerPool* pool_ = nullptr;
  };

  // All or nothing: queues every job, or none when they do not all fit (or after shutdown). Jobs taken by an idle
  // worker at once still count against the capacity until a worker picks them up, so capacity 0 means "only
  // when a worker is free". Held reservations count as queued jobs.
  bool try_submit(std::vector<Job> jobs);
  // The same, the first job taking the place `reservation` holds (consumed when the jobs are queued; kept when
  // they are not, and released with it).
  bool try_submit(std::vector<Job> jobs, Reservation& reservation);
  // A place for one job, or an empty reservation when the queue is full (or after shutdown).
  Reservation try_reserve();

  // Runs every queued job, then joins the workers. Idempotent.
  void shutdown();

  std::size_t queue_depth() const;
  int busy_workers() const;
  int workers() const { return worker_count_; }
  std::size_t capacity() const { return capacity_; }
  bool accepting() const;  // not shut down and at least one free slot

 private:
  void run();
  bool try_submit(std::vector<Job>& jobs, std::size_t reserved_by_caller);

  std::size_t capacity_;
  int worker_count_ = 0;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Job> queue_;
  std::size_t reserved_ = 0;  // places held by Reservations
  int busy_ = 0;
  int idle_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace wish::server
