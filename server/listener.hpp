#pragma once
// The accept loop of the service's listening socket, with a stop that loses no connection the kernel already
// accepted. The kernel completes a TCP handshake on its own and queues the connection (the backlog) until the
// process calls accept(); the client already sees it established and sends its request. Closing the listening
// socket resets whatever is still queued: clients see their request vanish (curl prints 000). So
// stop_accepting() ends the loop, run() then accepts every connection still queued, and only then closes the
// socket: later connects are refused (never accepted), earlier ones are all handed over. httplib's own loop
// closes at once; this replaces it (http_server.cpp). Socket-level only, free of httplib.

#include <functional>

#include "server/wake_latch.hpp"

namespace wish::server {

class Listener {
 public:
  // Takes ownership of a bound, listening socket (closed by run() once stopped, or by the destructor).
  explicit Listener(int listening_socket);
  ~Listener();
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;

  // Accepts connections and hands each accepted socket to on_accept (which owns it from then on) until
  // stop_accepting(); then hands over the connections still queued in the kernel and closes the listening socket.
  void run(const std::function<void(int socket)>& on_accept);
  // Thread-safe and idempotent; run() returns soon after (at once if it has not started: it only takes the queue).
  void stop_accepting() { stop_.set(); }

 private:
  // Accepts what is queued now; false once the queue is empty (or accept failed for another reason).
  bool accept_one(const std::function<void(int socket)>& on_accept);

  int fd_;
  WakeLatch stop_;
};

}  // namespace wish::server
