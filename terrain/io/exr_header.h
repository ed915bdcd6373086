// A check of an OpenEXR file's first header before OpenImageIO opens it:
// OpenEXR sizes its tables from the header, so a hostile dataWindow or
// attribute size would otherwise cost gigabytes before any limit applies.
#pragma once

#include <string>

#include "dem_options.h"

namespace aal {

// Walks the attributes of the first (part's) header: every attribute must
// fit inside the file, names must be terminated, the header must end, and
// dataWindow (box2i) must give a size within the DEM limits. Deep (non-image)
// files are refused. Throws InputError("PATH: ...") on any failure.
void checkExrHeader(const std::string& path, const DemLoadOptions& options);

}  // namespace aal
