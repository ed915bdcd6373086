// The exact-intersection table (terrain/light/cap_table.h) as the sampled R32F
// image the parity shaders read, uploaded and ready.
#pragma once

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/image.h"
#include "aperture/engine/vk/upload.h"
#include "aperture/shaders/config.h"
#include "aperture/terrain/light/cap_table.h"

namespace aal::test {

inline Image capTableImage(const Device& device, const CapIntersectionTable& table) {
  Image image(device, {AAL_CAP_TABLE_WIDTH, AAL_CAP_TABLE_HEIGHT, VK_FORMAT_R32_SFLOAT,
                       VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT});
  UploadBatch upload(device);
  upload.addImage(image, sizeof(float), table.values.data());
  upload.submit();
  return image;
}

}  // namespace aal::test
