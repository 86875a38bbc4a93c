#include "server/worker_pool.hpp"

#include "core/common/thread_policy.hpp"

namespace wish::server {

WorkerPool::WorkerPool(int workers, int queue_capacity)
    : capacity_(static_cast<std::size_t>(queue_capacity < 0 ? 0 : queue_capacity)) {
  if (workers < 1) workers = 1;
  worker_count_ = workers;
  threads_.reserve(static_cast<std::size_t>(workers));
  for (int i = 0; i < workers; ++i) threads_.emplace_back([this] { run(); });
}

WorkerPool::~WorkerPool() { shutdown(); }

bool WorkerPool::try_submit(std::vector<Job> jobs) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    // Idle workers take queued jobs immediately (even if they have not woken up yet), so they are free capacity
    // on top of the queue slots.
    if (queue_.size() + jobs.size() > capacity_ + static_cast<std::size_t>(idle_)) return false;
    for (auto& job : jobs) queue_.push_back(std::move(job));
  }
  cv_.notify_all();
  return true;
}

void WorkerPool::run() {
  limit_compute_threads_to_one();
  std::unique_lock lock(mutex_);
  for (;;) {
    ++idle_;
    cv_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    --idle_;
    if (queue_.empty()) return;  // stopping and drained
    Job job = std::move(queue_.front());
    queue_.pop_front();
    ++busy_;
    lock.unlock();
    job();
    lock.lock();
    --busy_;
  }
}

void WorkerPool::shutdown() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && threads_.empty()) return;
    stopping_ = true;
  }
  cv_.notify_all();
  for (auto& t : threads_)
    if (t.joinable()) t.join();
  threads_.clear();
}

std::size_t WorkerPool::queue_depth() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

int WorkerPool::busy_workers() const {
  std::lock_guard lock(mutex_);
  return busy_;
}

bool WorkerPool::accepting() const {
  std::lock_guard lock(mutex_);
  return !stopping_ && queue_.size() < capacity_ + static_cast<std::size_t>(idle_);
}

}  // namespace wish::server
