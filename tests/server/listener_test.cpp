// The listener's stop (listener.hpp): connections the kernel completed before it are handed over, not reset;
// connects after it are refused.
#include "server/listener.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace wish::server {
namespace {

// A listening socket on 127.0.0.1 at a free port; returns the port.
int listen_on_loopback(int& fd) {
  fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  EXPECT_EQ(::listen(fd, 64), 0);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  return ntohs(addr.sin_port);
}

// connect() to 127.0.0.1:port: the client's socket, or -errno.
int connect_to(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    const int e = errno;
    ::close(fd);
    return -e;
  }
  return fd;
}

// Connections the kernel completed while nobody called accept() (a busy accept loop, or one stopped at that very
// moment): their clients already sent requests. Stopping before run() starts leaves only the queue to take.
TEST(Listener, StopHandsOverEveryConnectionStillQueuedThenRefuses) {
  int fd = -1;
  const int port = listen_on_loopback(fd);
  std::vector<int> clients;
  for (int i = 0; i < 5; ++i) {
    clients.push_back(connect_to(port));
    ASSERT_GE(clients.back(), 0);
    ASSERT_EQ(::send(clients.back(), "GET / HTTP/1.1\r\n\r\n", 18, 0), 18);
  }
  Listener listener(fd);
  listener.stop_accepting();
  std::vector<int> accepted;
  listener.run([&](int sock) { accepted.push_back(sock); });
  EXPECT_EQ(accepted.size(), clients.size());
  for (int sock : accepted) {
    char buf[64];
    EXPECT_EQ(::recv(sock, buf, sizeof buf, 0), 18);  // the request that was sent is there to be answered
    ::close(sock);
  }
  EXPECT_EQ(connect_to(port), -ECONNREFUSED);  // the listening socket is closed
  for (int c : clients) ::close(c);
}

TEST(Listener, AcceptsWhileRunningAndReturnsOnStop) {
  int fd = -1;
  const int port = listen_on_loopback(fd);
  Listener listener(fd);
  std::atomic<int> accepted{0};
  std::thread loop([&] {
    listener.run([&](int sock) {
      ++accepted;
      ::close(sock);
    });
  });
  std::vector<int> clients;
  for (int i = 0; i < 3; ++i) clients.push_back(connect_to(port));
  listener.stop_accepting();
  loop.join();
  EXPECT_EQ(accepted.load(), 3);
  for (int c : clients) ::close(c);
}

}  // namespace
}  // namespace wish::server
