// Fixture for tests that use the GPU: one Vulkan context with validation on, and any
// validation error reported during a test fails that test.
#pragma once

#include <gtest/gtest.h>

#include "gpu/context.h"

namespace aquaform::testing {

class GpuTest : public ::testing::Test {
protected:
    /// The process-wide context (created on first use; the software device in CI).
    static gpu::Context& ctx();

    void SetUp() override;
    void TearDown() override;

private:
    uint32_t errors_at_start_ = 0;
};

}  // namespace aquaform::testing
