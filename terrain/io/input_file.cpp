#include "aperture/terrain/io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>
#include <system_error>

#include "aperture/terrain/errors.h"

namespace aal {

namespace {

namespace fs = std::filesystem;

bool startsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

// What the mode names when it is neither a regular file nor a folder.
std::string nonFileKind(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO, not a file";
  if (S_ISCHR(mode)) return "a character device, not a file";
  if (S_ISBLK(mode)) return "a block device, not a file";
  if (S_ISSOCK(mode)) return "a socket, not a file";
  return "not a regular file";
}

// "16 MiB (16777216 bytes)", "1000 bytes": the cap in a message.
std::string capText(uint64_t bytes) {
  const uint64_t mib = uint64_t{1} << 20;
  if (bytes >= mib && bytes % mib == 0) {
    return std::to_string(bytes / mib) + " MiB (" + std::to_string(bytes) + " bytes)";
  }
  return std::to_string(bytes) + " bytes";
}

}  // namespace

InputStatus inputStatus(const std::string& path) {
  struct stat status {};
  if (::stat(path.c_str(), &status) == 0) {
    if (S_ISREG(status.st_mode)) return {InputKind::File, ""};
    if (S_ISDIR(status.st_mode)) return {InputKind::Folder, ""};
    return {InputKind::Other, nonFileKind(status.st_mode)};
  }
  const int error = errno;
  if (error == ELOOP) {
    return {InputKind::Other, "a symbolic link loop (too many levels of symbolic links)"};
  }
  if (error == ENOENT || error == ENOTDIR) {
    struct stat link {};
    if (!path.empty() && ::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
      std::error_code ignored;
      return {InputKind::Other, "a symbolic link to " + fs::read_symlink(path, ignored).string() +
                                    ", which does not exist"};
    }
    return {InputKind::Missing, ""};
  }
  return {InputKind::Other, std::string("out of reach (") + std::strerror(error) + ")"};
}

InputKind requireFileOrFolder(const std::string& path, const std::string& subject) {
  const InputStatus status = inputStatus(path);
  if (status.kind == InputKind::Other) throw InputError(subject + " is " + status.what);
  return status.kind;
}

std::string readTextInput(const std::string& path, const std::string& kind, uint64_t maxBytes) {
  const std::string subject = kind + " " + path;
  switch (requireFileOrFolder(path, subject)) {
    case InputKind::Missing: throw InputError(subject + " does not exist");
    case InputKind::Folder: throw InputError(subject + " is a folder, not a file");
    default: break;
  }
  const std::string tooBig = subject + " holds more than the " + capText(maxBytes) + " a " + kind +
                             " may hold: is it the right file?";
  // Opened without blocking and looked at again through the descriptor: a
  // FIFO put in the file's place since would otherwise block the open.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError("cannot read " + subject + ": " + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat status {};
  if (::fstat(fd, &status) != 0) {
    throw InputError("cannot read " + subject + ": " + std::strerror(errno));
  }
  if (!S_ISREG(status.st_mode)) throw InputError(subject + " is " + nonFileKind(status.st_mode));
  if (static_cast<uint64_t>(status.st_size) > maxBytes) {
    throw InputError(tooBig + " (it holds " + std::to_string(status.st_size) + " bytes)");
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string text;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputError("cannot read " + subject + ": " + std::strerror(errno));
    if (n == 0) break;
    // A file that grew since its size was read is held to the cap too.
    if (text.size() + static_cast<size_t>(n) > maxBytes) throw InputError(tooBig);
    text.append(buffer, static_cast<size_t>(n));
  }
  if (startsWith(text, "\xEF\xBB\xBF")) text.erase(0, 3);  // UTF-8 byte order mark
  return text;
}

namespace {

// GDAL's virtual file systems that read files: over HTTP, and inside zip and
// gzip archives (docs/dem-input.md).
constexpr const char* kFileSystems[] = {"/vsicurl/", "/vsizip/", "/vsigzip/"};

// Drivers whose connection strings name a subdataset of a file, in the form
// GDAL lists them (SUBDATASET_N_NAME): the file is the quoted part, else
// the part after the prefix (NETCDF:file.nc:var), or after the directory
// number (GTIFF_DIR:1:file.tif).
constexpr const char* kSubdatasetDrivers[] = {"NETCDF", "HDF5", "HDF4_SDS", "HDF4_EOS",
                                              "GTIFF_DIR"};

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw InputError(path + ": " + why);
}

// "MEM" of "MEM:::DATAPOINTER=...": letters, digits, '_' and '-' before the
// first colon, as GDAL drivers recognise their connection strings.
std::optional<std::string> connectionPrefix(const std::string& path) {
  const size_t colon = path.find(':');
  if (colon == std::string::npos || colon == 0) return std::nullopt;
  for (size_t i = 0; i < colon; ++i) {
    const unsigned char c = static_cast<unsigned char>(path[i]);
    if (!std::isalnum(c) && c != '_' && c != '-') return std::nullopt;
  }
  return path.substr(0, colon);
}

std::string upper(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

// The file a subdataset name of `driver` names.
std::string subdatasetFile(const std::string& driver, const std::string& path) {
  const size_t open = path.find('"');
  if (open != std::string::npos) {
    const size_t close = path.find('"', open + 1);
    return path.substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1);
  }
  size_t start = driver.size() + 1;
  if (driver == "GTIFF_DIR") {
    const size_t colon = path.find(':', start);
    return colon == std::string::npos ? std::string() : path.substr(colon + 1);
  }
  const size_t end = path.find(':', start);
  return path.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

// Throws unless `file`, named inside `path`, is a regular file.
void requireNamedFile(const std::string& path, const std::string& file) {
  const InputStatus status = inputStatus(file);
  if (status.kind == InputKind::File) return;
  refuse(path, "names the file " + file + ", which " +
                   (status.kind == InputKind::Missing  ? std::string("does not exist")
                    : status.kind == InputKind::Folder ? std::string("is a folder")
                                                       : "is " + status.what));
}

// "/vsimem/" of "/vsimem/x.tif".
std::string fileSystemOf(const std::string& path) {
  const size_t slash = path.find('/', 1);
  return slash == std::string::npos ? path : path.substr(0, slash + 1);
}

// Refuses every /vsi path but those of kFileSystems (and /vsimem/ when
// `inMemory`); an archive on disk must be a regular file: GDAL would block
// on a FIFO as on any file.
void checkVirtualPath(const std::string& original, const std::string& path, bool inMemory) {
  if (inMemory && startsWith(path, "/vsimem/")) return;
  for (const char* system : kFileSystems) {
    if (!startsWith(path, system)) continue;
    if (std::strcmp(system, "/vsicurl/") == 0) return;
    std::string inner = path.substr(std::strlen(system));
    if (startsWith(inner, "{")) inner = inner.substr(1, inner.find('}') - 1);
    if (startsWith(inner, "/vsi")) return checkVirtualPath(original, inner, inMemory);
    // The archive: the first part of the path, folder by folder, that is
    // not a folder (for /vsigzip/, the whole).
    for (size_t end = inner.find('/', 1);; end = inner.find('/', end + 1)) {
      const std::string part = inner.substr(0, end);
      const InputStatus status = inputStatus(part);
      if (status.kind == InputKind::Other)
        refuse(original, "its archive " + part + " is " + status.what);
      if (status.kind != InputKind::Folder || end == std::string::npos) return;
    }
  }
  refuse(original, "is a path of GDAL's virtual file system " + fileSystemOf(path) +
                       ", not a file: aperture opens files, and through GDAL only /vsicurl/, "
                       "/vsizip/ and /vsigzip/ paths");
}

}  // namespace

std::string gdalFileName(const std::string& path, bool inMemoryFiles) {
  if (startsWith(path, "/vsi")) {
    checkVirtualPath(path, path, inMemoryFiles);
    return path;
  }
  const InputStatus status = inputStatus(path);
  if (status.kind == InputKind::Other) refuse(path, "is " + status.what);
  if (status.kind != InputKind::Missing) {
    // A name GDAL could take for a connection string or inline XML is a
    // file's when a file has it: "./" makes GDAL read it as one.
    const bool plain = startsWith(path, "/") || (path.find(':') == std::string::npos &&
                                                 !startsWith(path, "<") && !startsWith(path, "{"));
    return plain ? path : "./" + path;
  }
  if (const std::optional<std::string> prefix = connectionPrefix(path)) {
    const std::string driver = upper(*prefix);
    for (const char* subdatasets : kSubdatasetDrivers) {
      if (driver == subdatasets) {
        requireNamedFile(path, subdatasetFile(driver, path));
        return path;
      }
    }
    refuse(path,
           "is a GDAL connection string (" + *prefix +
               ":...), not a file: aperture opens files (and the subdatasets GDAL lists in them, "
               "and /vsicurl/, /vsizip/, /vsigzip/ paths)");
  }
  refuse(path, "no such file");
}

}  // namespace aal
