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

WorkerPool::Reservation& WorkerPool::Reservation::operator=(Reservation&& other) noexcept {
  if (this != &other) {
    release();
    pool_ = other.pool_;
    other.pool_ = nullptr;
  }
  return *this;
}

void WorkerPool::Reservation::release() {
  if (!pool_) return;
  {
    std::lock_guard lock(pool_->mutex_);
    --pool_->reserved_;
  }
  pool_ = nullptr;
}

bool WorkerPool::try_submit(std::vector<Job> jobs) { return try_submit(jobs, 0); }

bool WorkerPool::try_submit(std::vector<Job> jobs, Reservation& reservation) {
  if (reservation.pool_ != this) return try_submit(jobs, 0);
  if (!try_submit(jobs, 1)) return false;
  reservation.pool_ = nullptr;  // its place is now a queued job (try_submit took it off reserved_)
  return true;
}

bool WorkerPool::try_submit(std::vector<Job>& jobs, std::size_t reserved_by_caller) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return false;
    // Idle workers take queued jobs immediately (even if they have not woken up yet), so they are free capacity
    // on top of the queue slots; places held for other requests are taken.
    if (queue_.size() + (reserved_ - reserved_by_caller) + jobs.size() > capacity_ + static_cast<std::size_t>(idle_))
      return false;
    reserved_ -= reserved_by_caller;
    for (auto& job : jobs) queue_.push_back(std::move(job));
  }
  cv_.notify_all();
  return true;
}

WorkerPool::Reservation WorkerPool::try_reserve() {
  std::lock_guard lock(mutex_);
  if (stopping_ || queue_.size() + reserved_ + 1 > capacity_ + static_cast<std::size_t>(idle_)) return {};
  ++reserved_;
  return Reservation(this);
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
  return !stopping_ && queue_.size() + reserved_ < capacity_ + static_cast<std::size_t>(idle_);
}

}  // namespace wish::server
