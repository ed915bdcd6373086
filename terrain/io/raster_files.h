// The files a raster is made of, as GDAL reads them: the file itself, its
// sidecars (.aux.xml, .ovr, world files, masks) and, for a VRT, the rasters
// it reads (and theirs, for nested VRTs). A tool that writes one of them
// replaces the DEM's data as surely as one that writes the DEM's own file,
// so the tools check their outputs against all of them (tools/tool_paths.h;
// docs/dem-input.md, "Outputs").
#pragma once

#include <string>
#include <vector>

namespace aal {

// The files GDAL reads for the raster `path` (GDALDataset::GetFileList),
// `path` first, each once; nested VRTs are followed. Only a path that is a
// regular file (std::filesystem::is_regular_file, links followed) is
// opened: a folder, a FIFO, a device or a GDAL connection string
// ("MEM:::...", "/vsicurl/...") gives just `path`, and so does a file GDAL
// cannot open (the loader says why, later). Never throws for the raster's
// content; reads only headers.
std::vector<std::string> rasterFiles(const std::string& path);

}  // namespace aal
