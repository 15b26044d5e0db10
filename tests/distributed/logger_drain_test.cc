// The launcher's view of lcm-logger's sockets (launch/logger_drain.h): the
// run starts once the logger's receiving socket is bound. Sockets here are
// bound on the loopback address and never send anything.

#include "launch/logger_drain.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <optional>

namespace dynapath::launch {
namespace {

// A UDP socket bound to 127.0.0.1 on a port the kernel picks; its port.
int BoundUdpSocket(int& port) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) return -1;
  socklen_t size = sizeof address;
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
  port = ntohs(address.sin_port);
  return fd;
}

// A child that waits on a pipe (never written) until killed.
pid_t IdleChild(int wait_fd) {
  const pid_t pid = fork();
  if (pid == 0) {
    char byte = 0;
    while (read(wait_fd, &byte, 1) != 0) {
    }
    _exit(0);
  }
  return pid;
}

void Stop(pid_t pid) {
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
}

TEST(LoggerDrain, UdpmPortOfLcmUrls) {
  EXPECT_EQ(UdpmPort("udpm://239.255.76.67:7667?ttl=0"), 7667);
  EXPECT_EQ(UdpmPort("udpm://239.255.76.67:9000"), 9000);
  EXPECT_EQ(UdpmPort("udpm://239.255.76.67"), 7667);  // LCM's default
  EXPECT_EQ(UdpmPort("udpm://239.255.76.67?ttl=1"), 7667);
  EXPECT_EQ(UdpmPort("memq://"), std::nullopt);
  EXPECT_EQ(UdpmPort("udpm://239.255.76.67:0"), std::nullopt);
  EXPECT_EQ(UdpmPort("udpm://239.255.76.67:65536"), std::nullopt);
  EXPECT_EQ(UdpmPort("udpm://239.255.76.67:76x7"), std::nullopt);
}

TEST(LoggerDrain, ASocketInheritedFromTheLauncherIsNotTheLoggers) {
  int port = 0;
  const int fd = BoundUdpSocket(port);
  ASSERT_GE(fd, 0);
  int pipe_fds[2];
  ASSERT_EQ(pipe(pipe_fds), 0);
  const pid_t child = IdleChild(pipe_fds[0]);  // inherits fd, as lcm-logger would
  EXPECT_EQ(HasUdpSocketOnPort(child, port), std::optional<bool>(false));
  EXPECT_FALSE(WaitForLoggerToSubscribe(child, port, std::chrono::milliseconds(100)));
  Stop(child);
  close(fd);
  close(pipe_fds[0]);
  close(pipe_fds[1]);
}

TEST(LoggerDrain, WaitsUntilTheChildBindsThePort) {
  int port = 0;
  const int probe = BoundUdpSocket(port);  // a free port, given back below
  ASSERT_GE(probe, 0);
  close(probe);
  int pipe_fds[2];
  ASSERT_EQ(pipe(pipe_fds), 0);
  const pid_t child = fork();
  if (child == 0) {
    usleep(200'000);  // subscribes late
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(static_cast<uint16_t>(port));
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) _exit(1);
    char byte = 0;
    while (read(pipe_fds[0], &byte, 1) != 0) {
    }
    _exit(0);
  }
  EXPECT_EQ(HasUdpSocketOnPort(child, port), std::optional<bool>(false));
  EXPECT_TRUE(WaitForLoggerToSubscribe(child, port, std::chrono::seconds(3600)));
  EXPECT_EQ(HasUdpSocketOnPort(child, port), std::optional<bool>(true));
  Stop(child);
  close(pipe_fds[0]);
  close(pipe_fds[1]);
}

TEST(LoggerDrain, AnExitedLoggerEndsTheWaitAtOnce) {
  const pid_t child = fork();
  if (child == 0) _exit(1);
  // Not reaped: a zombie, as lcm-logger is until the launcher reaps it.
  // An hour's cap: only noticing the exit can pass this test.
  EXPECT_FALSE(WaitForLoggerToSubscribe(child, 7667, std::chrono::seconds(3600)));
  waitpid(child, nullptr, 0);
  EXPECT_FALSE(WaitForLoggerToSubscribe(child, 7667, std::chrono::seconds(3600)));
}

}  // namespace
}  // namespace dynapath::launch
