// Staging uploads (gpu/staging.h): inside a recording an upload is recorded in order with the
// commands around it instead of submitting; outside, an UploadBatch shares one submission; the
// surface renderer may re-make its grid (which uploads a table) while it records.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "render/surface_renderer.h"
#include "tests/gpu_test.h"
#include "tests/particle_cube.h"

namespace aquaform {
namespace {

class StagingTest : public testing::GpuTest {};

TEST_F(StagingTest, UploadsInsideARecordingLandInOrderWithTheCommandsAroundThem) {
    const size_t n = 100000;  // 400 kB: through staging memory (beyond vkCmdUpdateBuffer's 64 KiB)
    std::vector<uint32_t> big(n), small(16, 0xabcdu), zeros(n, 0u);
    std::iota(big.begin(), big.end(), 1u);
    gpu::Buffer a = gpu::create_buffer(ctx(), "test.a", n * 4), b = gpu::create_buffer(ctx(), "test.b", n * 4);
    const uint64_t before = ctx().submissions();
    ctx().submit_and_wait([&](VkCommandBuffer cmd) {
        // Through the tracked helpers, so that the barriers between them and the uploads are the
        // tracker's (the synchronization-validation run of this test checks them).
        gpu::fill(ctx(), cmd, a, 7u);  // an earlier write the upload must follow
        gpu::upload(ctx(), a, big.data(), n * 4);
        gpu::upload(ctx(), a, small.data(), small.size() * 4, 64);  // inline, over part of the big one
        gpu::copy(ctx(), cmd, a, b, VkBufferCopy{0, 0, n * 4});
        gpu::upload(ctx(), a, zeros.data(), n * 4);  // after the copy: b must not see it
    });
    EXPECT_EQ(ctx().submissions(), before + 1) << "uploads inside a recording submit nothing of their own";
    const auto got_b = gpu::download_vector<uint32_t>(ctx(), b, n);
    const auto got_a = gpu::download_vector<uint32_t>(ctx(), a, n);
    for (size_t i = 0; i < n; ++i) {
        const uint32_t want = i >= 16 && i < 32 ? 0xabcdu : big[i];
        ASSERT_EQ(got_b[i], want) << "word " << i;
        ASSERT_EQ(got_a[i], 0u) << "word " << i;
    }
    gpu::destroy_buffer(ctx(), a);
    gpu::destroy_buffer(ctx(), b);
}

TEST_F(StagingTest, UploadsInABatchShareOneSubmission) {
    std::vector<gpu::Buffer> buffers;
    for (int i = 0; i < 3; ++i) buffers.push_back(gpu::create_buffer(ctx(), "test.batch" + std::to_string(i), 1 << 20));
    std::vector<float> data(1 << 18);
    const uint64_t before = ctx().submissions();
    {
        gpu::UploadBatch batch(ctx());
        for (size_t i = 0; i < buffers.size(); ++i) {
            std::fill(data.begin(), data.end(), float(i) + 0.5f);
            gpu::upload(ctx(), buffers[i], data.data(), data.size() * 4);
        }
        EXPECT_EQ(ctx().submissions(), before) << "held until the batch closes";
    }
    EXPECT_EQ(ctx().submissions(), before + 1);
    for (size_t i = 0; i < buffers.size(); ++i) {
        const auto got = gpu::download_vector<float>(ctx(), buffers[i], data.size());
        EXPECT_EQ(got.front(), float(i) + 0.5f);
        EXPECT_EQ(got.back(), float(i) + 0.5f);
    }
    const uint64_t single = ctx().submissions();
    gpu::upload(ctx(), buffers[0], data.data(), 64);
    EXPECT_EQ(ctx().submissions(), single + 1) << "outside a batch an upload submits at once";
    for (auto& b : buffers) gpu::destroy_buffer(ctx(), b);
}

TEST_F(StagingTest, SurfaceRendererRemakesItsGridInsideTheRecordingAndDrawsTheSurface) {
    // A larger --radius re-makes the render grid inside record(); its Morton table is uploaded
    // in the recording (this used to fail with "submit_and_wait called inside a recording").
    testing::CubeScene cube(ctx(), glm::vec3(0.15f), 6);
    for (float radius : {0.0f, 2.5f, 3.0f}) {
        SurfaceSettings settings;
        settings.radius_spacings = radius;
        const SurfaceFrame frame = cube.render(settings);
        if (radius > 0.0f) {
            EXPECT_FLOAT_EQ(cube.renderer.grid().cell_size, radius * cube.kSpacing);
        }
        size_t hits = 0;
        for (size_t i = 0; i < frame.hit.size(); ++i) hits += frame.has_surface(i);
        EXPECT_GT(hits, 50u) << "radius " << radius << " spacings";
    }
}

}  // namespace
}  // namespace aquaform
