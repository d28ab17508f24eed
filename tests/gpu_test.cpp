#include "tests/gpu_test.h"

#include <memory>

namespace aquaform::testing {

gpu::Context& GpuTest::ctx() {
    static std::unique_ptr<gpu::Context> context =
        std::make_unique<gpu::Context>(gpu::ContextOptions{"", /*validation=*/true});
    return *context;
}

void GpuTest::SetUp() { errors_at_start_ = ctx().validation_errors(); }

void GpuTest::TearDown() {
    EXPECT_EQ(ctx().validation_errors(), errors_at_start_)
        << "Vulkan validation errors during this test; the last one: " << ctx().last_validation_message();
}

}  // namespace aquaform::testing
