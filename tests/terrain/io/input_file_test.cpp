// Inputs are what they claim to be (terrain/io/input_file.h): what a path
// names is said without opening it, text inputs are capped and may start
// with a byte order mark, and GDAL is given files, never a connection
// string. Every FIFO case runs under alarm(): a read that blocks ends the
// test instead of hanging it.
#include "aperture/terrain/io/input_file.h"

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "aperture/terrain/errors.h"
#include "aperture/tests/terrain/io/dem_test_util.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::expectMessage;
using test::inputErrorOf;

// Gives up the test (SIGALRM) should anything block on a FIFO.
struct NoHang {
  NoHang() { ::alarm(10); }
  ~NoHang() { ::alarm(0); }
};

TEST(InputFile, SaysWhatAPathIsWithoutOpeningIt) {
  NoHang guard;
  test::TempDir dir;
  const fs::path file = dir.path() / "f.txt", fifo = dir.path() / "fifo", loop = dir.path() / "a",
                 dangling = dir.path() / "dangling", socket = dir.path() / "s";
  std::ofstream(file) << "x";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  fs::create_symlink(dir.path() / "b", loop);
  fs::create_symlink(loop, dir.path() / "b");
  fs::create_symlink(dir.path() / "gone", dangling);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(socket.string().size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, socket.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);

  EXPECT_EQ(inputStatus(file.string()).kind, InputKind::File);
  EXPECT_EQ(inputStatus(dir.path().string()).kind, InputKind::Folder);
  EXPECT_EQ(inputStatus((dir.path() / "none").string()).kind, InputKind::Missing);
  EXPECT_EQ(inputStatus((file / "below").string()).kind, InputKind::Missing);
  struct Case {
    fs::path path;
    std::string what;
  };
  for (const Case& c :
       {Case{fifo, "a FIFO, not a file"}, Case{"/dev/zero", "a character device, not a file"},
        Case{socket, "a socket, not a file"},
        Case{loop, "a symbolic link loop (too many levels of symbolic links)"},
        Case{dangling,
             "a symbolic link to " + (dir.path() / "gone").string() + ", which does not exist"}}) {
    const InputStatus status = inputStatus(c.path.string());
    EXPECT_EQ(status.kind, InputKind::Other) << c.path;
    EXPECT_EQ(status.what, c.what) << c.path;
    EXPECT_EQ(
        inputErrorOf([&] { requireFileOrFolder(c.path.string(), "thing " + c.path.string()); }),
        "thing " + c.path.string() + " is " + c.what);
  }
  EXPECT_EQ(requireFileOrFolder(file.string(), "x"), InputKind::File);
  ::close(fd);
}

TEST(InputFile, TextInputsAreCappedNamedAndMayStartWithAByteOrderMark) {
  NoHang guard;
  test::TempDir dir;
  const fs::path bom = dir.path() / "bom.txt";
  std::ofstream(bom, std::ios::binary) << "\xEF\xBB\xBF"
                                       << "0 1 2 3\n";
  EXPECT_EQ(readTextInput(bom.string(), "ramp"), "0 1 2 3\n");
  // Only at the start.
  const fs::path inside = dir.path() / "inside.txt";
  std::ofstream(inside, std::ios::binary) << "a\xEF\xBB\xBF";
  EXPECT_EQ(readTextInput(inside.string(), "ramp"), "a\xEF\xBB\xBF");

  // A sparse file one byte over the cap: refused from its size, unread.
  const fs::path big = dir.path() / "big.txt";
  std::ofstream(big).close();
  fs::resize_file(big, kMaxTextInputBytes + 1);
  const auto start = std::chrono::steady_clock::now();
  expectMessage(
      inputErrorOf([&] { readTextInput(big.string(), "colour ramp"); }),
      {"colour ramp " + big.string(),
       "holds more than the 16 MiB (16777216 bytes) a colour ramp may hold", "16777217 bytes"});
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  // At the cap it reads.
  fs::resize_file(big, kMaxTextInputBytes);
  EXPECT_EQ(readTextInput(big.string(), "colour ramp").size(), kMaxTextInputBytes);
  // Another cap, stated as given.
  expectMessage(inputErrorOf([&] { readTextInput(bom.string(), "path", 4); }),
                {"more than the 4 bytes a path may hold"});

  const fs::path fifo = dir.path() / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  EXPECT_EQ(inputErrorOf([&] { readTextInput(fifo.string(), "camera path"); }),
            "camera path " + fifo.string() + " is a FIFO, not a file");
  EXPECT_EQ(inputErrorOf([&] { readTextInput("/dev/zero", "colour ramp"); }),
            "colour ramp /dev/zero is a character device, not a file");
  EXPECT_EQ(inputErrorOf([&] { readTextInput(dir.path().string(), "colour ramp"); }),
            "colour ramp " + dir.path().string() + " is a folder, not a file");
  EXPECT_EQ(inputErrorOf([&] { readTextInput((dir.path() / "none").string(), "colour ramp"); }),
            "colour ramp " + (dir.path() / "none").string() + " does not exist");
}

// Runs `f` with the working folder set to `folder`.
template <typename F>
void inFolder(const fs::path& folder, F&& f) {
  const fs::path before = fs::current_path();
  fs::current_path(folder);
  try {
    f();
  } catch (...) {
    fs::current_path(before);
    throw;
  }
  fs::current_path(before);
}

TEST(InputFile, GdalIsGivenFilesNeverConnectionStrings) {
  NoHang guard;
  test::TempDir dir;
  const std::string files = "aperture opens files";
  for (const std::string& connection :
       {std::string("MEM:::DATAPOINTER=0x1,PIXELS=10,LINES=10"), std::string("NUMPY:::0x1"),
        std::string("PG:dbname=x"), std::string("mem:::DATAPOINTER=0x1")}) {
    const std::string prefix = connection.substr(0, connection.find(':'));
    expectMessage(
        inputErrorOf([&] { gdalFileName(connection); }),
        {connection + ": is a GDAL connection string (" + prefix + ":...), not a file", files});
  }
  for (const std::string vsi :
       {"/vsimem/x.tif", "/vsistdin/", "/vsisubfile/0_100,/etc/passwd", "/vsis3/bucket/x.tif"}) {
    expectMessage(inputErrorOf([&] { gdalFileName(vsi); }),
                  {vsi + ": is a path of GDAL's virtual file system /vsi", files});
  }
  EXPECT_EQ(gdalFileName("/vsimem/x.tif", /*inMemoryFiles=*/true), "/vsimem/x.tif");
  EXPECT_EQ(gdalFileName("/vsicurl/https://example.org/dem.tif"),
            "/vsicurl/https://example.org/dem.tif");
  expectMessage(inputErrorOf([&] { gdalFileName("/vsizip//vsimem/a.zip/x.tif"); }),
                {"/vsizip//vsimem/a.zip/x.tif: is a path of GDAL's virtual file system /vsimem/"});

  // Archives on disk must be files.
  const fs::path fifo = dir.path() / "a.zip";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  expectMessage(inputErrorOf([&] { gdalFileName("/vsizip/" + fifo.string() + "/dem.tif"); }),
                {"its archive " + fifo.string() + " is a FIFO, not a file"});
  expectMessage(inputErrorOf([&] { gdalFileName("/vsigzip/" + fifo.string()); }),
                {"its archive " + fifo.string() + " is a FIFO, not a file"});
  EXPECT_EQ(gdalFileName("/vsizip/" + (dir.path() / "none.zip/x.tif").string()),
            "/vsizip/" + (dir.path() / "none.zip/x.tif").string());

  // Subdatasets of a file, as GDAL lists them: the file must be one.
  const fs::path nc = dir.path() / "d.nc";
  std::ofstream(nc) << "x";
  const std::string quotedNc = "NETCDF:\"" + nc.string() + "\":elevation";
  EXPECT_EQ(gdalFileName(quotedNc), quotedNc);
  EXPECT_EQ(gdalFileName("GTIFF_DIR:2:" + nc.string()), "GTIFF_DIR:2:" + nc.string());
  expectMessage(inputErrorOf([&] { gdalFileName("NETCDF:\"missing.nc\":z"); }),
                {"names the file missing.nc, which does not exist"});
  expectMessage(inputErrorOf([&] { gdalFileName("HDF5:\"" + fifo.string() + "\"://z"); }),
                {"names the file " + fifo.string() + ", which is a FIFO, not a file"});

  // Files, whatever their names; one GDAL would take for a connection
  // string is given to it as a path.
  EXPECT_EQ(gdalFileName(nc.string()), nc.string());
  EXPECT_EQ(inputErrorOf([&] { gdalFileName(fifo.string()); }),
            fifo.string() + ": is a FIFO, not a file");
  EXPECT_EQ(inputErrorOf([&] { gdalFileName((dir.path() / "none.tif").string()); }),
            (dir.path() / "none.tif").string() + ": no such file");
  std::ofstream(dir.path() / "MEM:::x") << "x";
  inFolder(dir.path(), [&] {
    EXPECT_EQ(gdalFileName("MEM:::x"), "./MEM:::x");
    EXPECT_EQ(gdalFileName("d.nc"), "d.nc");
  });
  EXPECT_EQ(gdalFileName((dir.path() / "MEM:::x").string()), (dir.path() / "MEM:::x").string());
}

}  // namespace
}  // namespace aal
