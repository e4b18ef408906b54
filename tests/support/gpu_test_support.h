// A fixture for GPU tests: one Vulkan context with the Khronos validation layer enabled; a test
// fails when the layer reported anything while it ran.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "omnisweep/gpu/context.h"

namespace omnisweep::testing {

class ValidatedGpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  static void TearDownTestSuite();
  void TearDown() override;
  static gpu::Context& context() { return *context_; }

 private:
  static std::unique_ptr<gpu::Context> context_;
};

}  // namespace omnisweep::testing
