#include "server/connection_threads.hpp"

#include <algorithm>

namespace wish::server {

ConnectionThreads::ConnectionThreads(std::size_t warm_threads, std::size_t max_threads)
    : max_threads_(std::max<std::size_t>(1, max_threads)) {
  std::lock_guard lock(mutex_);
  for (std::size_t i = 0; i < std::min(warm_threads, max_threads_); ++i) threads_.emplace_back([this] { run(); });
}

ConnectionThreads::~ConnectionThreads() { shutdown(); }

void ConnectionThreads::enqueue(std::function<void()> task) {
  std::lock_guard lock(mutex_);
  queue_.push_back(std::move(task));
  // A thread for every task that finds no idle one, up to the cap.
  if (queue_.size() > idle_ && threads_.size() < max_threads_ && !stopping_)
    threads_.emplace_back([this] { run(); });
  else
    cv_.notify_one();
}

void ConnectionThreads::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    ++idle_;
    cv_.wait(lock, [&] { return !queue_.empty() || stopping_; });
    --idle_;
    if (queue_.empty()) return;  // stopping, nothing left
    auto task = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    task();
    lock.lock();
  }
}

void ConnectionThreads::shutdown() {
  std::vector<std::thread> threads;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    threads.swap(threads_);
  }
  cv_.notify_all();
  for (auto& t : threads) t.join();
}

std::size_t ConnectionThreads::threads() const {
  std::lock_guard lock(mutex_);
  return threads_.size();
}

std::size_t ConnectionThreads::busy() const {
  std::lock_guard lock(mutex_);
  return threads_.size() >= idle_ ? threads_.size() - idle_ : 0;
}

std::size_t ConnectionThreads::waiting() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

}  // namespace wish::server
