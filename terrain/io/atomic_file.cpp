#include "aperture/terrain/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>

#include "aperture/terrain/interrupt.h"

namespace aal {

namespace fs = std::filesystem;

namespace {

// fsync of a file or folder: "" when done, else why not. A folder that
// cannot be synced (EINVAL: some file systems; EROFS) has nothing to flush.
std::string syncPath(const fs::path& path, bool folder) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (folder ? O_DIRECTORY : 0));
  if (fd < 0) return "cannot open " + path.string() + " to flush it: " + std::strerror(errno);
  int result;
  do {
    result = ::fsync(fd);
  } while (result != 0 && errno == EINTR);
  const int why = errno;
  ::close(fd);
  if (result != 0 && !(folder && (why == EINVAL || why == EROFS))) {
    return "cannot flush " + path.string() + " to its disk: " + std::strerror(why);
  }
  return "";
}

// What a path that is not a regular file is, in words.
std::string kindOf(fs::file_type type) {
  switch (type) {
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::fifo: return "a FIFO (a pipe)";
    case fs::file_type::socket: return "a socket";
    default: return "not a regular file";
  }
}

// The folder of the kernel's devices and interfaces (/dev, /proc, /sys) that
// `path` lies in, by its own name or where its links lead; empty when none.
// Entries there are device nodes and kernel files: a write renamed onto one
// replaces the node with a regular file (as root, /dev/null itself).
std::string systemFolderOf(const fs::path& path) {
  std::error_code error;
  const fs::path absolute = fs::absolute(path, error).lexically_normal();
  const fs::path canonical = fs::weakly_canonical(absolute, error);
  // A link that leads nowhere yet (weakly_canonical keeps it as it is) would
  // create its target.
  fs::path target = absolute;
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(target, error)); ++hops) {
    const fs::path next = fs::read_symlink(target, error);
    if (error) break;
    target = next.is_absolute() ? next : target.parent_path() / next;
  }
  target = fs::weakly_canonical(target, error);
  for (const fs::path& p : {absolute, canonical, target}) {
    auto part = p.begin();
    if (part == p.end() || *part != "/" || ++part == p.end()) continue;
    for (const char* folder : {"dev", "proc", "sys"}) {
      if (*part == folder) return std::string("/") + folder;
    }
  }
  return {};
}

}  // namespace

void checkOutputWritable(const fs::path& path) {
  if (path.empty()) throw std::runtime_error("output path is empty");
  std::error_code error;
  // Followed through symbolic links: what a write would reach.
  const fs::file_status status = fs::status(path, error);
  if (fs::is_directory(status)) {
    throw std::runtime_error("output " + path.string() + " is a folder, not a file");
  }
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    std::string link;
    if (fs::is_symlink(fs::symlink_status(path, error))) {
      link = " (a link to " + fs::read_symlink(path, error).string() + ")";
    }
    throw std::runtime_error("output " + path.string() + link + " is " + kindOf(status.type()) +
                             ", not a file: outputs are written to regular files only; "
                             "give the path of a file");
  }
  if (const std::string system = systemFolderOf(path); !system.empty()) {
    throw std::runtime_error("output " + path.string() + " is in " + system +
                             ", which holds devices and kernel files, not files to write: "
                             "give the path of a file elsewhere");
  }
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, error)) {
    throw std::runtime_error("cannot write " + path.string() + ": folder " + folder.string() +
                             " does not exist");
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    throw std::runtime_error("cannot write " + path.string() + ": folder " + folder.string() +
                             " is not writable");
  }
}

namespace {

// The PID in ".NAME.tmp-PID-N[.EXT]", or 0 when the name is not ours.
pid_t temporaryOwner(const std::string& name) {
  if (name.empty() || name[0] != '.') return 0;
  const size_t tag = name.rfind(".tmp-");
  if (tag == std::string::npos) return 0;
  size_t i = tag + 5;
  long pid = 0;
  const size_t digits = i;
  while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i])) && pid < 1 << 30) {
    pid = pid * 10 + (name[i++] - '0');
  }
  if (i == digits || i >= name.size() || name[i] != '-') return 0;
  const size_t counter = ++i;
  while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i]))) ++i;
  if (i == counter || (i < name.size() && name[i] != '.')) return 0;
  return static_cast<pid_t>(pid);
}

}  // namespace

bool isTemporaryName(const std::string& name) {
  return temporaryOwner(name) > 0;
}

void removeDeadTemporaries(const fs::path& folder) {
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    const pid_t owner = temporaryOwner(entry.path().filename().string());
    if (owner <= 0 || !entry.is_regular_file(error)) continue;
    if (::kill(owner, 0) != 0 && errno == ESRCH) fs::remove(entry.path(), error);
  }
}

namespace {
std::atomic<bool> removeOnWrite{true};

// The temporaries being written, for the interrupt watchdog to remove when
// it ends a tool that did not unwind in time (terrain/interrupt.h).
std::timed_mutex liveMutex;
std::set<std::string>& liveTemporaries() {
  static std::set<std::string>* live = new std::set<std::string>;  // outlives exit
  return *live;
}

void removeLiveTemporaries() {
  if (!liveMutex.try_lock_for(std::chrono::milliseconds(100))) return;
  for (const std::string& path : liveTemporaries()) ::unlink(path.c_str());
  liveMutex.unlock();
}

void addLiveTemporary(const fs::path& path) {
  std::error_code error;
  const std::string absolute = fs::absolute(path, error).string();
  std::lock_guard lock(liveMutex);
  liveTemporaries().insert(absolute.empty() ? path.string() : absolute);
  setInterruptCleanup(removeLiveTemporaries);
}

void dropLiveTemporary(const fs::path& path) {
  std::error_code error;
  const std::string absolute = fs::absolute(path, error).string();
  std::lock_guard lock(liveMutex);
  liveTemporaries().erase(absolute.empty() ? path.string() : absolute);
}

}  // namespace

void setRemoveDeadTemporariesOnWrite(bool remove) {
  removeOnWrite.store(remove);
}

AtomicOutput::AtomicOutput(fs::path path) : final_(std::move(path)) {
  checkOutputWritable(final_);
  if (removeOnWrite.load()) {
    removeDeadTemporaries(final_.has_parent_path() ? final_.parent_path() : fs::path("."));
  }
  static std::atomic<unsigned> counter{0};
  const std::string unique = std::to_string(::getpid()) + "-" + std::to_string(counter++);
  // Built with += : GCC 12 reports a false -Wrestrict for chained + here.
  std::string name = ".";
  name += final_.stem().string();
  name += ".tmp-";
  name += unique;
  name += final_.extension().string();
  temporary_ = final_.parent_path() / name;
  addLiveTemporary(temporary_);
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove(temporary_, ignored);
  }
  dropLiveTemporary(temporary_);
}

void AtomicOutput::commit() {
  // The file's data reach the disk before its name does: a rename alone is
  // atomic against a killed process, but after a power loss the file system
  // may hold the new name with an empty or partial file behind it.
  if (const std::string failed = syncPath(temporary_, false); !failed.empty()) {
    throw std::runtime_error("cannot write " + final_.string() + ": " + failed);
  }
  std::error_code error;
  fs::rename(temporary_, final_, error);
  if (error) {
    throw std::runtime_error("cannot move " + temporary_.string() + " to " + final_.string() +
                             ": " + error.message());
  }
  committed_ = true;
  // And the rename itself: the folder's entry.
  const fs::path folder = final_.has_parent_path() ? final_.parent_path() : fs::path(".");
  if (const std::string failed = syncPath(folder, true); !failed.empty()) {
    throw std::runtime_error("cannot write " + final_.string() + ": " + failed);
  }
}

std::runtime_error AtomicOutput::failure(const std::string& detail, const std::string& what) const {
  std::string message = detail;
  // Writers name the file they were given; the user knows the output's name.
  for (const std::string& name : {temporary_.string(), temporary_.filename().string()}) {
    for (size_t at = message.find(name); at != std::string::npos;
         at = message.find(name, at + final_.string().size())) {
      message.replace(at, name.size(), final_.string());
    }
  }
  std::string lower = message;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const fs::path folder = final_.has_parent_path() ? final_.parent_path() : fs::path(".");
  std::error_code error;
  const fs::space_info space = fs::space(folder, error);
  // GDAL and OpenEXR report a full disk as "error writing tag data" or
  // "file output failed"; say it in plain words (the limit is a few blocks).
  if (!error && space.available < (uintmax_t{1} << 20) &&
      lower.find("no space left") == std::string::npos) {
    message += "; no space left on device (" + std::to_string(space.available) + " bytes free in " +
               folder.string() + ")";
  }
  return std::runtime_error("cannot write " + (what.empty() ? "" : what + " ") + final_.string() +
                            ": " + message);
}

}  // namespace aal
