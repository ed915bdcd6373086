// Memory limits refuse cleanly: the budget (terrain/io/memory_budget.h)
// honours AAL_MEMORY_LIMIT, ulimit -v and the cgroups' limits (v2 and v1, in a
// fake hierarchy), an in-memory bake is refused before
// it allocates, a Vulkan driver that cannot start under an address-space
// limit is said to be limited, not missing, and an allocation that fails
// anyway ends the tool with exit 1 and a message that says memory.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <new>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "aperture/terrain/io/memory_budget.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"
#include "aperture/tools/tool_main.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runShell;
using test::runTool;
using test::TempDir;

#if defined(__SANITIZE_ADDRESS__)
// AddressSanitizer reserves terabytes of address space: no ulimit -v fits.
constexpr bool kAddressSpaceLimitsWork = false;
#else
constexpr bool kAddressSpaceLimitsWork = true;
#endif

TEST(MemoryLimit, AnInMemoryBakeIsRefusedBeforeItAllocates) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 512, 512);
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " -q",
                         "AAL_MEMORY_LIMIT=3M");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("holding its bake in memory (22 bytes per texel) needs 5.8 MB"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("(AAL_MEMORY_LIMIT)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--tile-size"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.path() / "a.exr"));
}

// GIS rasters alone sum no aperture map: 16 bytes per texel less, so a
// limit that refuses the map's bake (5.8 MB above) lets them through.
TEST(MemoryLimit, RastersWithoutAMapCountNoApertureSums) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 512, 512);
  const fs::path svf = dir.path() / "svf.tif";
  const auto tight =
      runTool("aal-bake", quoted(dem) + " --svf " + quoted(svf) + " -q", "AAL_MEMORY_LIMIT=2M");
  EXPECT_EQ(tight.exitCode, 2) << tight.out;
  EXPECT_NE(tight.out.find("holding its bake in memory (10 bytes per texel) needs 2.6 MB"),
            std::string::npos)
      << tight.out;
  // The tiles need their folder.
  EXPECT_NE(tight.out.find("bake it in tiles (-o FOLDER --tile-size 4096"), std::string::npos)
      << tight.out;
  EXPECT_FALSE(fs::exists(svf));
  const auto r =
      runTool("aal-bake", quoted(dem) + " --svf " + quoted(svf) + " -q", "AAL_MEMORY_LIMIT=4M");
  EXPECT_EQ(r.exitCode, 0) << r.out;
  EXPECT_TRUE(fs::exists(svf));
}

TEST(MemoryLimit, AnAddressSpaceLimitIsTheBudget) {
  if (!kAddressSpaceLimitsWork) GTEST_SKIP() << "AddressSanitizer build";
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 3000, 3000);
  const auto r = runShell("ulimit -v 350000; " + (test::binDir() / "aal-bake").string() + " " +
                          quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " -q");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("of memory is available (ulimit -v)"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.path() / "a.exr"));
}

// RLIMIT_DATA (ulimit -d), posed with prlimit as a job scheduler would.
TEST(MemoryLimit, ADataLimitIsTheBudget) {
  if (!kAddressSpaceLimitsWork) GTEST_SKIP() << "AddressSanitizer build";
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 3000, 3000);
  const auto r = runShell("prlimit --data=150000000 " + (test::binDir() / "aal-bake").string() +
                          " " + quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " -q");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("of memory is available (ulimit -d)"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.path() / "a.exr"));
}

TEST(MemoryLimit, AVulkanDriverUnderATightLimitIsSaidToBeLimitedNotMissing) {
  if (!kAddressSpaceLimitsWork) GTEST_SKIP() << "AddressSanitizer build";
  TempDir dir;
  const fs::path dem = fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif";
  const auto r = runShell("ulimit -v 1000000; " + (test::binDir() / "aal-render").string() + " " +
                          quoted(dem) + " -o " + quoted(dir.path() / "r.png") + " --size 64x64");
  EXPECT_EQ(r.exitCode, 1) << r.out;  // not a signal (a crash is 128 + n)
  EXPECT_NE(r.out.find("ulimit -v 1000000 kB"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("install one"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// Every address-space limit from where the tools barely load to where they
// work: each run ends within 10 s (GDAL's worker pool used to wait for ever
// when some of its threads could not start), never by a signal (GDAL's
// fatal allocation errors aborted, and a static initialiser of the image
// plugin's libraries threw std::bad_alloc through dlopen), and a failure
// says memory. Below ~170 MB the loader itself cannot map the libraries
// (exit 127 before main), which no tool can help.
TEST(MemoryLimit, NoToolHangsOrAbortsUnderAnyAddressSpaceLimit) {
  if (!kAddressSpaceLimitsWork) GTEST_SKIP() << "AddressSanitizer build";
  TempDir dir;
  const fs::path dem = fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif";
  const std::string out = quoted(dir.path() / "out");
  const std::vector<std::pair<std::string, std::string>> runs = {
      {"aal-bake", quoted(dem) + " -q -o " + out + ".exr"},
      {"aal-relief", quoted(dem) + " -q -o " + out + ".tif"},
      {"aal-render", quoted(dem) + " --mode reference --size 32x18 -q -o " + out + ".png"},
  };
  int worked = 0;
  // 10 MB apart near the edge, where the libraries' own allocations fail
  // (GDAL's metadata reader and PROJ ended the process at 180 and 200 MB).
  for (int megabytes = 150; megabytes <= 750; megabytes += megabytes < 250 ? 10 : 50) {
    for (const auto& [tool, arguments] : runs) {
      const std::string command = "ulimit -v " + std::to_string(megabytes * 1000) +
                                  "; timeout -s KILL 10 " + (test::binDir() / tool).string() + " " +
                                  arguments;
      const auto r = runShell(command);
      if (r.exitCode == 127 &&
          r.out.find("error while loading shared libraries") != std::string::npos) {
        continue;  // the dynamic loader, before main
      }
      EXPECT_TRUE(r.exitCode == 0 || r.exitCode == 1 || r.exitCode == 2) << command << "\n"
                                                                         << r.out;
      if (r.exitCode == 0) ++worked;
      if (r.exitCode == 1 || r.exitCode == 2) {
        EXPECT_TRUE(r.out.find("memory") != std::string::npos ||
                    r.out.find("address space") != std::string::npos)
            << command << "\n"
            << r.out;
      }
    }
  }
  EXPECT_GT(worked, 0) << "no run fitted under 750 MB";
}

int runThrowing(const std::function<int()>& body, std::string& printed) {
  CLI::App app("test", "aal-test");
  char name[] = "aal-test";
  char* argv[] = {name, nullptr};
  testing::internal::CaptureStderr();
  const int code = runToolBody(app, 1, argv, body);
  printed = testing::internal::GetCapturedStderr();
  return code;
}

TEST(ToolMain, AFailedAllocationIsExitOneWithAMessageThatSaysMemory) {
  std::string printed;
  EXPECT_EQ(runThrowing([]() -> int { throw std::bad_alloc(); }, printed), kExitFailure);
  EXPECT_EQ(printed.rfind("aal-test: error: out of memory", 0), 0u) << printed;
  EXPECT_EQ(runThrowing(
                []() -> int {
                  throw std::system_error(
                      std::make_error_code(std::errc::resource_unavailable_try_again), "thread");
                },
                printed),
            kExitFailure);
  EXPECT_NE(printed.find("cannot start a thread"), std::string::npos) << printed;
  EXPECT_NE(printed.find("out of memory"), std::string::npos) << printed;
}

TEST(MemoryBudget, NamesTheTightestLimit) {
  setenv("AAL_MEMORY_LIMIT", "5M", 1);
  const std::optional<MemoryLimit> limit = memoryLimit();
  unsetenv("AAL_MEMORY_LIMIT");
  ASSERT_TRUE(limit.has_value());
  EXPECT_EQ(limit->bytes, 5u << 20);
  EXPECT_EQ(limit->source, "AAL_MEMORY_LIMIT");
  const std::optional<MemoryLimit> system = memoryLimit();
  ASSERT_TRUE(system.has_value());  // /proc/meminfo at least
  EXPECT_GT(system->bytes, 0u);
  EXPECT_NE(outOfMemoryMessage("reading").find("out of memory while reading"), std::string::npos);
}

// A fake cgroup hierarchy (AAL_CGROUP_ROOT) with `file` = `limit` and
// `usageFile` = `used` at its root, which limits every process whatever its
// cgroup's path: the budget walks up to it.
void writeCgroupRoot(const fs::path& root, const std::string& folder, const std::string& file,
                     const std::string& limit, const std::string& usageFile,
                     const std::string& used) {
  fs::create_directories(root / folder);
  std::ofstream(root / folder / file) << limit << "\n";
  std::ofstream(root / folder / usageFile) << used << "\n";
}

std::optional<MemoryLimit> limitUnder(const fs::path& root) {
  const std::string saved = std::getenv("AAL_MEMORY_LIMIT") ? std::getenv("AAL_MEMORY_LIMIT") : "";
  unsetenv("AAL_MEMORY_LIMIT");
  setenv("AAL_CGROUP_ROOT", root.c_str(), 1);
  std::optional<MemoryLimit> limit = memoryLimit();
  unsetenv("AAL_CGROUP_ROOT");
  if (!saved.empty()) setenv("AAL_MEMORY_LIMIT", saved.c_str(), 1);
  return limit;
}

TEST(MemoryBudget, ACgroupV2LimitLessItsUseIsTheBudget) {
  TempDir dir;
  writeCgroupRoot(dir.path(), ".", "memory.max", std::to_string(200u << 20), "memory.current",
                  std::to_string(50u << 20));
  const std::optional<MemoryLimit> limit = limitUnder(dir.path());
  ASSERT_TRUE(limit.has_value());
  EXPECT_EQ(limit->bytes, uint64_t{150} << 20);
  EXPECT_EQ(limit->source, "cgroup memory.max");
  // "max" is no limit.
  writeCgroupRoot(dir.path(), ".", "memory.max", "max", "memory.current", "0");
  const std::optional<MemoryLimit> none = limitUnder(dir.path());
  ASSERT_TRUE(none.has_value());
  EXPECT_NE(none->source, "cgroup memory.max");
}

TEST(MemoryBudget, ACgroupV1LimitLessItsUseIsTheBudget) {
  TempDir dir;
  writeCgroupRoot(dir.path(), "memory", "memory.limit_in_bytes", std::to_string(300u << 20),
                  "memory.usage_in_bytes", std::to_string(100u << 20));
  const std::optional<MemoryLimit> limit = limitUnder(dir.path());
  ASSERT_TRUE(limit.has_value());
  EXPECT_EQ(limit->bytes, uint64_t{200} << 20);
  EXPECT_EQ(limit->source, "cgroup memory.limit_in_bytes");
  // v1 writes "no limit" as a number near 2^63.
  writeCgroupRoot(dir.path(), "memory", "memory.limit_in_bytes", "9223372036854771712",
                  "memory.usage_in_bytes", "0");
  const std::optional<MemoryLimit> none = limitUnder(dir.path());
  ASSERT_TRUE(none.has_value());
  EXPECT_NE(none->source, "cgroup memory.limit_in_bytes");
}

TEST(MemoryLimit, ABakeOverItsCgroupsLimitIsRefusedNamingIt) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 512, 512);
  const fs::path root = dir.path() / "cgroup";
  writeCgroupRoot(root, ".", "memory.max", std::to_string(4u << 20), "memory.current",
                  std::to_string(1u << 20));
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " -q",
                         "-u AAL_MEMORY_LIMIT AAL_CGROUP_ROOT=" + quoted(root));
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("needs 5.8 MB, but only 3.1 MB of memory is available (cgroup memory.max)"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(dir.path() / "a.exr"));
}

}  // namespace
}  // namespace aal
