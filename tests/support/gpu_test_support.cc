#include "tests/support/gpu_test_support.h"

namespace omnisweep::testing {

std::unique_ptr<gpu::Context> ValidatedGpuTest::context_;

void ValidatedGpuTest::SetUpTestSuite() {
  if (!context_) {
    gpu::ContextOptions options = gpu::ContextOptions::from_environment();
    options.validation = true;
    context_ = std::make_unique<gpu::Context>(options);
  }
}

void ValidatedGpuTest::TearDownTestSuite() { context_.reset(); }

void ValidatedGpuTest::TearDown() {
  for (const std::string& message : context_->take_validation_messages()) {
    ADD_FAILURE() << "Vulkan validation: " << message;
  }
}

}  // namespace omnisweep::testing
