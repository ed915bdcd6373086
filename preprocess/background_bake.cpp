#include "aperture/preprocess/background_bake.h"

#include <stdexcept>
#include <utility>

namespace aal {

BackgroundBake::BackgroundBake(std::shared_ptr<const Heightfield> field, std::string demPath,
                               BakeOptions options)
    : field_(std::move(field)) {
  options.cancel = &cancel_;
  options.progress = [this](double fraction) { progress_.store(fraction); };
  thread_ = std::thread([this, demPath = std::move(demPath), options = std::move(options)] {
    try {
      CachedAperture cached = cachedOrBakedAperture(*field_, demPath, options, /*quiet=*/true);
      result_.path = cached.path;
      result_.horizons = std::move(cached.horizons);
      if (cached.path.empty()) {
        result_.map = toHalfApertureMap(cached.map);
      } else {
        ApertureMapReader reader(cached.path.string());
        checkApertureMatchesDem(reader.header(), cached.path.string(), *field_, demPath);
        result_.map = readHalfApertureMap(reader);
      }
      progress_.store(1.0);
    } catch (...) {
      error_ = std::current_exception();
    }
    finished_.store(true);
  });
}

BackgroundBake::~BackgroundBake() {
  cancel();
  if (thread_.joinable()) thread_.join();
}

BakedAperture BackgroundBake::take() {
  if (!finished()) throw std::logic_error("BackgroundBake::take before the bake finished");
  if (thread_.joinable()) thread_.join();
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  return std::move(result_);
}

}  // namespace aal
