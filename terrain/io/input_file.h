// Inputs are what they claim to be (docs/dem-input.md, "Every input is a
// file"): every path a user names is looked at before it is opened, so that
// a FIFO (whose open blocks until a writer comes, for ever), a device
// (/dev/zero reads without end), a socket or a symbolic link loop is refused
// with a message that says what it is; text inputs are read with a cap; and
// GDAL is given files, never a connection string (`MEM:::DATAPOINTER=...`
// made GDAL read memory at any address the user wrote).
#pragma once

#include <cstdint>
#include <string>

namespace aal {

// What a path names, as the readers below tell it apart.
enum class InputKind {
  Missing,  // nothing there
  File,     // a regular file (through symbolic links)
  Folder,   // a folder (through symbolic links)
  Other,    // anything else: see InputStatus::what
};

struct InputStatus {
  InputKind kind = InputKind::Missing;
  // For Other, what it is, to follow "PATH is " in a message: "a FIFO, not a
  // file", "a character device, not a file", "a block device, not a file",
  // "a socket, not a file", "a symbolic link loop (too many levels of
  // symbolic links)", "a symbolic link to TARGET, which does not exist", or
  // "out of reach (REASON)" when the system cannot say (permissions on a
  // folder above it, a name too long).
  std::string what;
};

// What is at `path`, following symbolic links; never opens it.
InputStatus inputStatus(const std::string& path);

// Throws InputError("SUBJECT is WHAT") when `path` is neither a regular
// file nor a folder nor missing (InputKind::Other); returns the kind
// otherwise, for the caller to say its own "missing" and "folder" (a DEM
// folder may be a raster to GDAL, an aperture map folder a tiled map).
// `subject` starts the message: "colour ramp /tmp/x", or "/tmp/x:" for the
// DEM messages that start with the path.
InputKind requireFileOrFolder(const std::string& path, const std::string& subject);

// The most a text input (a colour ramp, a camera path) may hold: 16 MiB,
// thousands of times any real one, so that a mistaken path (a disk image, a
// log) is refused at once instead of being read whole into memory.
constexpr uint64_t kMaxTextInputBytes = uint64_t{16} << 20;

// The text of the file at `path`, with a UTF-8 byte order mark at its start
// dropped (editors on Windows write one). Throws InputError naming the file
// as `kind PATH` (e.g. "colour ramp x.txt") when it is missing, a folder,
// not a regular file (requireFileOrFolder), cannot be read, or holds more
// than `maxBytes` (checked from its size before reading, and again while
// reading, should it grow).
std::string readTextInput(const std::string& path, const std::string& kind,
                          uint64_t maxBytes = kMaxTextInputBytes);

// The name to give GDAL for the raster a user named `path`, which must be a
// file (a folder too, which some GDAL drivers read: an Arc/Info binary
// grid), or one of the paths GDAL reads files through: `/vsicurl/`,
// `/vsizip/`, `/vsigzip/` (an archive on disk must be a regular file), and
// the subdatasets of a file (`NETCDF:"file.nc":var`, `HDF5:...`,
// `HDF4_SDS:...`, `HDF4_EOS:...`, `GTIFF_DIR:N:file.tif`, whose file must be a
// regular file), as GDAL lists them. Throws InputError, starting with the
// path, for a connection string of any other driver (`MEM:::`, `NUMPY:::`,
// `PG:`, ...), any other `/vsi` path (`/vsimem/`, `/vsistdin/`,
// `/vsisubfile/`, ...) and what requireFileOrFolder refuses; a path that
// names nothing gives "PATH: no such file". A file whose name reads like a
// connection string (`MEM:::x` in the working folder) is a file: it comes
// back as `./MEM:::x`, which GDAL opens as that file. `inMemoryFiles` also
// lets `/vsimem/` through: GDAL's in-memory files, which programs (the
// fuzzers) make themselves and no user path names.
std::string gdalFileName(const std::string& path, bool inMemoryFiles = false);

}  // namespace aal
