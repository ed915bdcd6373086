// Outputs written to a temporary file in the destination folder and renamed
// into place, so an interrupted or failed write never leaves a broken file and
// an existing file is replaced atomically.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace aal {

// Throws std::runtime_error when `path` cannot be created or replaced (missing
// folder, no permission, is a folder), and when it is not a file to write:
// an existing path that is not a regular file (a device, a FIFO, a socket;
// symbolic links followed) or any path in /dev, /proc or /sys. The rename
// onto such a path would replace the node itself with a regular file
// (docs/dem-input.md, "Outputs"). Call it before long work starts.
void checkOutputWritable(const std::filesystem::path& path);

// Removes the temporary files (".NAME.tmp-PID-N.EXT") in `folder` whose
// process is gone: what a killed run left behind. Files of live processes,
// other files and sub-folders are kept; errors are ignored (a hint of
// tidiness, not a guarantee). AtomicOutput calls it on its folder.
void removeDeadTemporaries(const std::filesystem::path& folder);
// Whether `name` (a file name, no folder) has the form of those temporaries,
// ".NAME.tmp-PID-N[.EXT]": a file of that name in an output's folder is
// removed by a write there once process PID is gone.
bool isTemporaryName(const std::string& name);
// Whether AtomicOutput calls it (on unless turned off). The ranks of an MPI
// bake turn it off: their folder is written from other hosts at the same
// time, and a PID names a process only on its own host, so a live rank's
// temporary would look dead from another (preprocess/mpi_tiled_bake.h).
void setRemoveDeadTemporariesOnWrite(bool remove);

class AtomicOutput {
 public:
  // Checks that `path` is writable (see checkOutputWritable) and picks a
  // unique temporary name next to it, keeping the extension so writers that
  // choose a format by extension still work.
  explicit AtomicOutput(std::filesystem::path path);
  // Removes the temporary file unless commit() succeeded.
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::filesystem::path& temporaryPath() const { return temporary_; }
  const std::filesystem::path& finalPath() const { return final_; }

  // Flushes the temporary file to its disk (fsync), renames it onto the
  // final path and flushes the folder, so that after a power loss the name
  // holds the whole new file or the old one (docs/dem-input.md, "Outputs").
  void commit();

  // The error to throw when writing the temporary failed with `detail`:
  // "cannot write [WHAT ]FINAL: DETAIL", with the temporary's name replaced
  // by the output's and "no space left on device" said when the output's
  // file system is full and `detail` does not say so.
  std::runtime_error failure(const std::string& detail, const std::string& what = "") const;

 private:
  std::filesystem::path final_;
  std::filesystem::path temporary_;
  bool committed_ = false;
};

}  // namespace aal
