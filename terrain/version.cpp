#include "aperture/terrain/version.h"

// Generated at build time by cmake/VersionInfo.cmake into the build tree.
#include "version_info.h"

namespace aal {

const char* versionNumber() {
  return kVersionNumber;
}

const char* gitRevision() {
  return kGitRevision;
}

std::string versionLine(const std::string& program) {
  std::string line = program + " " + kVersionNumber;
  if (kGitRevision[0] != '\0') line += std::string(" (") + kGitRevision + ")";
  return line;
}

std::string softwareName() {
  return versionLine("aperture");
}

}  // namespace aal
