#pragma once
// The HTTP connection threads (one task per accepted connection, for the connection's whole life, reading with
// a timeout: http_server.cpp). A fixed pool of N threads is starved by N idle or slow clients: measured before, 50
// half-open connections against 42 threads kept /healthz from answering for 30 s. Here a thread is started on demand
// for each connection that finds none idle, up to `max_threads` (the connection cap); so /healthz finds a thread as
// long as fewer than `max_threads` connections are open, and a silent connection frees its thread after the read
// timeout. Connections beyond the cap wait in FIFO order for a thread; at shutdown they are still served (a queued
// connection's request is an accepted one). Idle threads stay for reuse. `warm_threads` are started at once:
// starting a thread under load takes milliseconds.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace wish::server {

class ConnectionThreads {
 public:
  ConnectionThreads(std::size_t warm_threads, std::size_t max_threads);
  ~ConnectionThreads();  // shutdown()
  ConnectionThreads(const ConnectionThreads&) = delete;
  ConnectionThreads& operator=(const ConnectionThreads&) = delete;

  void enqueue(std::function<void()> task);
  // Runs what is queued, then joins every thread. Idempotent.
  void shutdown();

  std::size_t threads() const;  // started so far
  std::size_t busy() const;     // running a task
  std::size_t waiting() const;  // queued for a thread (only at the cap)

 private:
  void run();

  const std::size_t max_threads_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> queue_;
  std::vector<std::thread> threads_;
  std::size_t idle_ = 0;
  bool stopping_ = false;
};

}  // namespace wish::server
