// Which aperture this is: the version from the project() line of the top
// CMakeLists.txt and the git revision the build was made from. Tools print
// it for --version; aperture maps, tiled-bake folders and GeoTIFF outputs
// record softwareName() so that a file says what wrote it.
#pragma once

#include <string>

namespace aal {

// "0.2.0".
const char* versionNumber();

// The abbreviated commit the build was made from, e.g. "abc1234"; "" when
// the sources were not a git checkout (a release tarball).
const char* gitRevision();

// "aperture 0.2.0 (abc1234)", or "aperture 0.2.0" without a revision.
std::string softwareName();

// What `program --version` prints: "aal-bake 0.2.0 (abc1234)".
std::string versionLine(const std::string& program);

}  // namespace aal
