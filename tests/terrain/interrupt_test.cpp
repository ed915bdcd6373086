// The tools' interrupt handling (terrain/interrupt.h): whatever a tool is
// doing, it ends within a second of the first SIGINT, SIGTERM or SIGHUP and
// leaves no temporary behind; a second signal of any kind kills at once; a
// cleared interrupt lets the program go on.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>

#include "aperture/terrain/interrupt.h"
#include "aperture/tests/tools/run_tool.h"

extern char** environ;

namespace aal {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::string kProbe = AAL_INTERRUPT_PROBE;

// Starts the probe with `arguments`, its stdout on a pipe; returns its pid.
pid_t spawnProbe(const std::vector<std::string>& arguments, int& readEnd) {
  int pipeEnds[2];
  if (pipe(pipeEnds) != 0) return -1;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipeEnds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipeEnds[0]);
  std::vector<char*> argv = {const_cast<char*>(kProbe.c_str())};
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (posix_spawn(&pid, kProbe.c_str(), &actions, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  close(pipeEnds[1]);
  readEnd = pipeEnds[0];
  return pid;
}

// Blocks until the probe printed "ready" (its handler is in place).
bool waitReady(int readEnd) {
  char text[16] = {};
  const ssize_t n = read(readEnd, text, sizeof text - 1);
  return n > 0 && std::string(text).rfind("ready", 0) == 0;
}

class InterruptWatchdog : public testing::TestWithParam<int> {};

TEST_P(InterruptWatchdog, EndsAToolThatDoesNotUnwindWithinASecond) {
  const int signal = GetParam();
  test::TempDir dir;
  const fs::path output = dir.path() / "out.tif";
  int readEnd = -1;
  const pid_t pid = spawnProbe({"stuck", output.string()}, readEnd);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(waitReady(readEnd));
  close(readEnd);
  ASSERT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()), 1)
      << "the probe's temporary";
  const auto sent = Clock::now();
  kill(pid, signal);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  const double seconds = std::chrono::duration<double>(Clock::now() - sent).count();
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + signal);
  EXPECT_GE(seconds, kInterruptGraceSeconds * 0.9);  // it waited for the tool to unwind
  EXPECT_LT(seconds, 1.0 + 1.0);                     // 1 s, plus a margin for a loaded machine
  EXPECT_TRUE(fs::is_empty(dir.path())) << "a temporary was left behind";
}

INSTANTIATE_TEST_SUITE_P(EverySignal, InterruptWatchdog, testing::Values(SIGINT, SIGTERM, SIGHUP),
                         [](const testing::TestParamInfo<int>& signal) {
                           return std::string(sigabbrev_np(signal.param));
                         });

TEST(Interrupt, ASecondSignalOfAnotherKindKillsAtOnce) {
  test::TempDir dir;
  int readEnd = -1;
  const pid_t pid = spawnProbe({"stuck", (dir.path() / "out.tif").string()}, readEnd);
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(waitReady(readEnd));
  close(readEnd);
  const auto sent = Clock::now();
  kill(pid, SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  const double seconds = std::chrono::duration<double>(Clock::now() - sent).count();
  ASSERT_TRUE(WIFSIGNALED(status)) << "exited " << WEXITSTATUS(status);
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_LT(seconds, kInterruptGraceSeconds);  // before the watchdog's turn
}

TEST(Interrupt, AClearedInterruptStandsTheWatchdogDown) {
  int readEnd = -1;
  const pid_t pid = spawnProbe({"cleared"}, readEnd);
  ASSERT_GT(pid, 0);
  close(readEnd);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace aal
