// Outputs through a temporary file renamed into place (terrain/io/atomic_file.h),
// and the sweep of temporaries that killed runs left behind (a killed
// render's 11.8 MB cache temporary must not stay forever).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "aperture/terrain/io/atomic_file.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

void touch(const fs::path& path) {
  std::ofstream(path) << "x";
}

TEST(AtomicOutput, RemovesTheTemporariesOfDeadProcessesOnly) {
  test::TempDir dir;
  const std::string dead = std::to_string(test::deadPid()), alive = std::to_string(::getpid());
  const fs::path killed = dir.path() / (".k.tmp-" + dead + "-0.exr");
  const fs::path killedNoExtension = dir.path() / (".index.tmp-" + dead + "-12");
  const fs::path live = dir.path() / (".k.tmp-" + alive + "-3.exr");
  const fs::path notOurs = dir.path() / (".k.tmp-" + dead + "-x.exr");
  const fs::path visible = dir.path() / ("k.tmp-" + dead + "-0.exr");
  for (const fs::path& p : {killed, killedNoExtension, live, notOurs, visible}) touch(p);
  fs::create_directory(dir.path() / (".d.tmp-" + dead + "-0"));

  AtomicOutput output(dir.path() / "result.png");
  EXPECT_FALSE(fs::exists(killed));
  EXPECT_FALSE(fs::exists(killedNoExtension));
  EXPECT_TRUE(fs::exists(live)) << "a running process's temporary is kept";
  EXPECT_TRUE(fs::exists(notOurs));
  EXPECT_TRUE(fs::exists(visible));
  EXPECT_TRUE(fs::is_directory(dir.path() / (".d.tmp-" + dead + "-0")));
}

// Turned off (the ranks of an MPI bake, whose folder other hosts write at
// the same time), a write leaves every temporary; turned on again, it
// sweeps as before.
TEST(AtomicOutput, TheSweepAtEveryWriteCanBeTurnedOff) {
  test::TempDir dir;
  const fs::path killed = dir.path() / (".k.tmp-" + std::to_string(test::deadPid()) + "-0.exr");
  touch(killed);
  setRemoveDeadTemporariesOnWrite(false);
  { AtomicOutput output(dir.path() / "result.png"); }
  EXPECT_TRUE(fs::exists(killed));
  setRemoveDeadTemporariesOnWrite(true);
  { AtomicOutput output(dir.path() / "result.png"); }
  EXPECT_FALSE(fs::exists(killed));
}

TEST(AtomicOutput, CommitRenamesAndAnAbandonedOutputLeavesNothing) {
  test::TempDir dir;
  const fs::path final = dir.path() / "out.txt";
  {
    AtomicOutput abandoned(final);
    touch(abandoned.temporaryPath());
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
  AtomicOutput output(final);
  touch(output.temporaryPath());
  output.commit();
  EXPECT_TRUE(fs::exists(final));
  EXPECT_FALSE(fs::exists(output.temporaryPath()));
}

TEST(AtomicOutput, FailuresNameTheOutputNotItsTemporary) {
  test::TempDir dir;
  const fs::path final = dir.path() / "map.exr";
  const AtomicOutput output(final);
  const std::string detail = "Failed to write pixel data to image file \"" +
                             output.temporaryPath().string() + "\" (" +
                             output.temporaryPath().filename().string() + ")";
  const std::string message = output.failure(detail, "aperture map").what();
  EXPECT_EQ(message, "cannot write aperture map " + final.string() +
                         ": Failed to write pixel data to image file \"" + final.string() + "\" (" +
                         final.string() + ")");
  EXPECT_EQ(message.find(".tmp-"), std::string::npos);
  // Room on the disk: nothing about space is added.
  EXPECT_EQ(std::string(output.failure("GDAL failed").what()).find("no space"), std::string::npos);
}

// Writes go to regular files only: renamed onto /dev/null (as root) the
// temporary replaced the device node with a regular file, and /dev/stdout's
// link with one. Only the check runs here: nothing is ever written there,
// whatever it says.
TEST(AtomicOutput, DevicesFifosAndSystemFoldersAreNoOutputs) {
  test::TempDir dir;
  const auto refusal = [](const fs::path& path) {
    try {
      checkOutputWritable(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("/dev/null").find("output /dev/null is a character device, not a file"),
            std::string::npos)
      << refusal("/dev/null");
  // A pipe or a terminal, as the test runs; never accepted.
  EXPECT_NE(refusal("/dev/stdout").find(", not a file"), std::string::npos)
      << refusal("/dev/stdout");
  for (const char* path : {"/dev/aal-test-no-such.png", "/dev/shm/aal-test-no-such.png",
                           "/proc/self/aal-test.csv", "/sys/aal-test.tif"}) {
    const std::string folder =
        fs::path(path).begin()->string() + std::next(fs::path(path).begin())->string();
    EXPECT_NE(refusal(path).find("is in " + folder + ", which holds devices and kernel files"),
              std::string::npos)
        << path << ": " << refusal(path);
  }
  const fs::path fifo = dir.path() / "pipe.png", link = dir.path() / "null.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  fs::create_symlink("/dev/null", link);
  EXPECT_NE(refusal(fifo).find("is a FIFO (a pipe), not a file"), std::string::npos)
      << refusal(fifo);
  EXPECT_NE(refusal(link).find("null.png (a link to /dev/null) is a character device, not a file"),
            std::string::npos)
      << refusal(link);
  // A link into /dev that leads nowhere yet would create a file there.
  fs::create_symlink("/dev/aal-test-no-such.png", dir.path() / "dangling.png");
  EXPECT_NE(refusal(dir.path() / "dangling.png").find("is in /dev"), std::string::npos);
  // AtomicOutput checks the same, so every writer refuses them.
  EXPECT_THROW(AtomicOutput{link}, std::runtime_error);
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // Ordinary files, new or existing, still are.
  touch(dir.path() / "old.png");
  EXPECT_EQ(refusal(dir.path() / "old.png"), "accepted");
  EXPECT_EQ(refusal(dir.path() / "new.png"), "accepted");
}

}  // namespace
}  // namespace aal
