// Fixture for tests that run on a Vulkan device (lavapipe in CI) with the
// validation layer on; any validation message fails the test.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/instance.h"

namespace aal {

class VulkanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    InstanceOptions options;
    options.validation = true;
    instance_ = std::make_unique<Instance>(options);
    device_ = std::make_unique<Device>(*instance_);
  }

  void TearDown() override {
    device_.reset();  // destruction is validated too
    for (const std::string& message : instance_->validationLog().messages()) {
      ADD_FAILURE() << message;
    }
    EXPECT_EQ(instance_->validationLog().count(), 0u) << "validation messages";
    instance_.reset();
  }

  const Device& device() const { return *device_; }

  std::unique_ptr<Instance> instance_;
  std::unique_ptr<Device> device_;
};

}  // namespace aal
