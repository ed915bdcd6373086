// ProgressReporter's GDAL and JSON forms on stdout, captured (docs/cli.md,
// "Progress for scripts").
#include "aperture/preprocess/progress_reporter.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

namespace aal {
namespace {

// GDAL's line for `ticks` of 40, written out by hand: "0", then for each
// 2.5 % a dot, or the percentage at every tenth.
std::string gdalLine(int ticks) {
  std::string line = "0";
  for (int tick = 1; tick <= ticks; ++tick) {
    const int percentTimesTen = tick * 25;  // 2.5 % per tick
    line += percentTimesTen % 100 == 0 ? std::to_string(percentTimesTen / 10) : ".";
  }
  if (ticks == 40) line += " - done.\n";
  return line;
}

TEST(ProgressReporter, GdalWritesEveryTickPassedAndNoneTwice) {
  testing::internal::CaptureStdout();
  {
    ProgressReporter progress(ProgressStyle::Gdal, "baking", "baking");
    for (double f : {0.0, 0.1, 0.26, 0.26, 0.2, 0.5, 0.99}) progress.update(f);
    std::fflush(stdout);
    EXPECT_EQ(testing::internal::GetCapturedStdout(), gdalLine(39));  // 0.99: 39 ticks
    testing::internal::CaptureStdout();
    progress.update(1.0);
    progress.finish();
  }
  EXPECT_EQ(testing::internal::GetCapturedStdout(), "100 - done.\n");  // the 40th tick
  EXPECT_EQ(gdalLine(40), "0...10...20...30...40...50...60...70...80...90...100 - done.\n");
}

TEST(ProgressReporter, GdalStageCutShortEndsItsLine) {
  testing::internal::CaptureStdout();
  {
    ProgressReporter progress(ProgressStyle::Gdal, "baking", "baking");
    progress.update(0.3);
  }  // destroyed: finished where it stood
  EXPECT_EQ(testing::internal::GetCapturedStdout(), gdalLine(12) + "\n");
}

TEST(ProgressReporter, JsonHoldsDoneWhereItStoodAndWritesTheLastLine) {
  testing::internal::CaptureStdout();
  {
    ProgressReporter progress(ProgressStyle::Json, "rendering", "frames", 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(120));
    progress.updateDone(6);
    // Within 100 ms of the last line: held back, then written by finish.
    progress.updateDone(4);  // less than reported: held at 6
    progress.updateDone(7);
    progress.finish();
    progress.updateDone(10);  // after finish: nothing
  }
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string prefix = "{\"stage\":\"rendering\",\"done\":";
  std::vector<std::string> lines;
  size_t start = 0;
  for (size_t end; (end = out.find('\n', start)) != std::string::npos; start = end + 1) {
    lines.push_back(out.substr(start, end - start));
  }
  EXPECT_EQ(start, out.size()) << "the last line is not ended: " << out;
  ASSERT_EQ(lines.size(), 3u) << out;
  EXPECT_EQ(lines[0].rfind(prefix + "0,\"total\":10,\"seconds\":0.0", 0), 0u) << lines[0];
  EXPECT_EQ(lines[1].rfind(prefix + "6,\"total\":10,\"seconds\":", 0), 0u) << lines[1];
  EXPECT_EQ(lines[2].rfind(prefix + "7,\"total\":10,\"seconds\":", 0), 0u) << lines[2];
}

TEST(ProgressReporter, JsonWritesTheTotalAtOnceAndNeverAgain) {
  testing::internal::CaptureStdout();
  {
    ProgressReporter progress(ProgressStyle::Json, "baking", "baking");
    progress.update(0.5);  // held, unless 100 ms have passed since the first line
    progress.update(1.0);  // the total: written at once
    progress.update(1.0);
  }
  const std::string out = testing::internal::GetCapturedStdout();
  const size_t total = out.find("\"done\":1000,\"total\":1000");
  ASSERT_NE(total, std::string::npos) << out;
  EXPECT_EQ(out.find("\"done\":1000", total + 1), std::string::npos) << out;
}

TEST(ProgressReporter, NoneAndBarWriteNothingOnStdout) {
  for (ProgressStyle style : {ProgressStyle::None, ProgressStyle::Bar}) {
    testing::internal::CaptureStdout();
    {
      ProgressReporter progress(style, "baking", "baking");
      progress.update(0.5);
      progress.update(1.0);
    }
    EXPECT_EQ(testing::internal::GetCapturedStdout(), "");
  }
}

TEST(ProgressStyleNames, ParseBackToTheirStyles) {
  EXPECT_EQ(parseProgressStyle("bar"), ProgressStyle::Bar);
  EXPECT_EQ(parseProgressStyle("gdal"), ProgressStyle::Gdal);
  EXPECT_EQ(parseProgressStyle("json"), ProgressStyle::Json);
  EXPECT_EQ(parseProgressStyle("none"), ProgressStyle::None);
  EXPECT_EQ(parseProgressStyle("JSON"), std::nullopt);
  for (const char* name : kProgressStyleNames) EXPECT_TRUE(parseProgressStyle(name)) << name;
}

}  // namespace
}  // namespace aal
