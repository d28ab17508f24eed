// Debug names (VK_EXT_debug_utils): buffers, pipelines and timed passes carry their names into
// Vulkan, so a validation message says which buffer and which pass it is about. Each test
// misuses a named object on purpose in a context of its own with validation on, and never
// submits the misuse (the recording throws, so Context::submit ends it unsubmitted).

#include <gtest/gtest.h>

#include <string>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/context.h"
#include "gpu/timer.h"

namespace aquaform::testing {
namespace {

struct NotSubmitted {};  // thrown to end a recording unsubmitted

TEST(DebugNames, ValidationMessageNamesTheBufferAndTheTimedPassesAroundIt) {
    gpu::Context ctx(gpu::ContextOptions{"", /*validation=*/true});
    ASSERT_TRUE(ctx.debug_names()) << "the loader offers no VK_EXT_debug_utils";
    gpu::BufferSet buffers(ctx);
    const gpu::Buffer& misused = buffers.add("test.misused", 256);
    gpu::GpuTimer timer(ctx);
    EXPECT_THROW(ctx.submit_and_wait([&](VkCommandBuffer cmd) {
        timer.reset(cmd);
        gpu::GpuScope outer(&timer, cmd, "test.outer_pass");
        gpu::GpuScope inner(&timer, cmd, "test.inner_pass");
        const VkBufferCopy past_the_end{0, 512, 4};  // past its end: VUID-vkCmdCopyBuffer-dstOffset-00114
        vkCmdCopyBuffer(cmd, misused.buffer, misused.buffer, 1, &past_the_end);
        throw NotSubmitted{};
    }),
                 NotSubmitted);
    ASSERT_EQ(ctx.validation_errors(), 1u);
    const std::string message = ctx.last_validation_message();
    EXPECT_NE(message.find("objects: VkBuffer \"test.misused\""), std::string::npos) << message;
    EXPECT_NE(message.find("in: \"test.inner_pass\" < \"test.outer_pass\""), std::string::npos) << message;
}

TEST(DebugNames, ValidationMessageNamesTheComputePipelineByItsShader) {
    gpu::Context ctx(gpu::ContextOptions{"", /*validation=*/true});
    const gpu::ComputePass pass(ctx, {.shader = "render/gather.comp"});
    ASSERT_EQ(ctx.validation_errors(), 0u) << ctx.last_validation_message();
    EXPECT_THROW(ctx.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pass.pipeline());
        vkCmdDispatch(cmd, 1, 1, 1);  // none of its buffers bound
        throw NotSubmitted{};
    }),
                 NotSubmitted);
    ASSERT_GE(ctx.validation_errors(), 1u);
    const std::string message = ctx.last_validation_message();
    EXPECT_NE(message.find("VkPipeline \"render/gather.comp\""), std::string::npos) << message;
}

}  // namespace
}  // namespace aquaform::testing
