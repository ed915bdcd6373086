// Outputs through a temporary file renamed into place (terrain/io/atomic_file.h),
// and the sweep of temporaries that killed runs left behind (issue 17, item
// 9: a killed render's 11.8 MB cache temporary stayed forever).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
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

}  // namespace
}  // namespace aal
