// A raster's header checked against the bytes of its file before anything of
// the size it declares is allocated (docs/dem-input.md, "Limits"): a file of a
// few hundred kilobytes can claim gigabytes of samples.
#pragma once

#include <string>

class GDALDataset;
class GDALRasterBand;

namespace aal {

// Throws InputError("PATH: ...") when the samples `dataset` declares for
// `band` cannot come from its file: for a TIFF, a block outside the file,
// blocks that together claim more bytes than it has, or more samples than
// their codec can expand those bytes to; for a PNG, more samples than zlib's
// best ratio (1032:1) gives its bytes. Other formats, files of unknown size
// and TIFFs of more than a million blocks pass unchecked.
void checkDeclaredSizeFitsTheFile(const std::string& path, GDALDataset& dataset,
                                  GDALRasterBand& band);

}  // namespace aal
