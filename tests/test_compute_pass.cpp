// Compute passes take their bindings by the names the shader declares (read back from SPIR-V):
// the reflection finds names, numbers and access; a dispatch with a misnamed, missing or doubled
// binding is refused with a message naming the shader and the binding.
#include <gtest/gtest.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/context.h"
#include "gpu/shader_registry.h"
#include "gpu/spirv_reflect.h"
#include "render/surface_renderer.h"
#include "tests/gpu_test.h"
#include "tests/particle_cube.h"

namespace aquaform {
namespace {

class ComputePassTest : public testing::GpuTest {};

TEST(SpirvReflect, TheRayMarchDeclaresItsTwentyThreeBuffersByName) {
    const auto bindings = gpu::reflect_bindings(gpu::find_shader("render/ray_march.comp"), "render/ray_march.comp");
    ASSERT_EQ(bindings.size(), 23u);
    const char* names[] = {"params",       "sorted",        "cell_rank",  "cell_start",    "mask",
                           "coarse",       "depth_all",     "depth_agg",  "normal_screen", "rays",
                           "ray_count",    "hit",           "normal",     "march_cut",     "resume_rays",
                           "resume_count", "resume_state",  "ray_counts", "blend_weights", "depth_splash_back",
                           "shape",        "class_density", "spray"};
    for (uint32_t i = 0; i < 23; ++i) {
        EXPECT_EQ(bindings[i].binding, i);
        EXPECT_EQ(bindings[i].name, names[i]);
    }
    EXPECT_TRUE(bindings[0].reads);  // readonly
    EXPECT_FALSE(bindings[0].writes);
    EXPECT_FALSE(bindings[11].reads);  // writeonly hit
    EXPECT_TRUE(bindings[11].writes);
    EXPECT_TRUE(bindings[13].reads && bindings[13].writes);  // march_cut: read and written
}

TEST(SpirvReflect, TexelBuffersCarryTheirFormatAndParameterBlocksAreUniform) {
    // The lambda pass reads its parameters as a uniform block and its neighbours' positions and
    // the grid through storage texel buffers (grid_query.glsl says why); the pass must bind
    // each with its own descriptor type and view format.
    const auto bindings = gpu::reflect_bindings(gpu::find_shader("sim/pbf_lambda.comp"), "sim/pbf_lambda.comp");
    auto find = [&](const std::string& name) {
        for (const auto& b : bindings)
            if (b.name == name) return b;
        ADD_FAILURE() << "no binding " << name;
        return gpu::ShaderBinding{};
    };
    const gpu::ShaderBinding params = find("params"), p = find("p"), rank = find("cell_rank"), q = find("q");
    EXPECT_FALSE(params.storage);
    EXPECT_EQ(params.texel_format, 0u);
    EXPECT_TRUE(p.storage);
    EXPECT_EQ(p.texel_format, 1u);  // SPIR-V Rgba32f
    EXPECT_FALSE(p.writes);
    EXPECT_EQ(rank.texel_format, 33u);  // R32ui
    EXPECT_EQ(q.texel_format, 0u);      // written as a plain storage buffer
    EXPECT_TRUE(q.writes);
}

TEST(SpirvReflect, EveryEmbeddedComputeShaderNamesEachBindingOnce) {
    for (const gpu::EmbeddedShader& s : gpu::embedded_shaders()) {
        if (!s.name.ends_with(".comp")) continue;
        const auto bindings = gpu::reflect_bindings(s.spirv, s.name);
        for (size_t i = 0; i < bindings.size(); ++i) {
            EXPECT_FALSE(bindings[i].name.empty()) << s.name << " binding " << bindings[i].binding;
            for (size_t j = 0; j < i; ++j) EXPECT_NE(bindings[i].name, bindings[j].name) << s.name;
        }
    }
}

TEST_F(ComputePassTest, ADispatchWithAWrongOrMissingNameIsRefusedNamingIt) {
    gpu::ComputePass pass(ctx(), {"render/ray_args.comp", 2, 0, 1});
    gpu::Buffer a = gpu::create_buffer(ctx(), "test.count", 16), b = gpu::create_buffer(ctx(), "test.groups", 16);
    auto refused = [&](gpu::Bindings bindings) {
        try {
            ctx().submit_and_wait([&](VkCommandBuffer cmd) { gpu::dispatch(ctx(), cmd, pass, 1, bindings); });
        } catch (const Failure& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    const std::string wrong = refused({{"ray_count", &a}, {"groupz", &b}});
    EXPECT_NE(wrong.find("render/ray_args.comp"), std::string::npos) << wrong;
    EXPECT_NE(wrong.find("'groupz'"), std::string::npos) << wrong;
    const std::string missing = refused({{"ray_count", &a}});
    EXPECT_NE(missing.find("render/ray_args.comp"), std::string::npos) << missing;
    EXPECT_NE(missing.find("'group_counts' (binding 1) is not given"), std::string::npos) << missing;
    const std::string twice = refused({{"ray_count", &a}, {"ray_count", &b}});
    EXPECT_NE(twice.find("given twice"), std::string::npos) << twice;
    gpu::destroy_buffer(ctx(), a);
    gpu::destroy_buffer(ctx(), b);
}

}  // namespace
}  // namespace aquaform

namespace aquaform {
namespace {

class BarrierTest : public testing::GpuTest {};

TEST_F(BarrierTest, ABarrierOnlyWhereADispatchDependsOnAnEarlierCommand) {
    // ray_args reads ray_count and writes group_counts.
    gpu::ComputePass pass(ctx(), {"render/ray_args.comp", 2, 0, 1});
    std::vector<gpu::Buffer> b;
    for (int i = 0; i < 5; ++i) b.push_back(gpu::create_buffer(ctx(), "test.b" + std::to_string(i), 16));
    std::vector<uint64_t> after;
    ctx().submit_and_wait([&](VkCommandBuffer cmd) {
        const gpu::BarrierTracker& t = ctx().tracker();
        const uint64_t start = t.barriers();
        auto count = [&] { after.push_back(t.barriers() - start); };
        gpu::dispatch(ctx(), cmd, pass, 1, {{"ray_count", &b[0]}, {"group_counts", &b[1]}});
        count();  // reads a buffer nobody wrote: none
        gpu::dispatch(ctx(), cmd, pass, 1, {{"ray_count", &b[0]}, {"group_counts", &b[2]}});
        count();  // reads what the first read, writes another: none
        gpu::dispatch(ctx(), cmd, pass, 1, {{"ray_count", &b[1]}, {"group_counts", &b[3]}});
        count();  // reads what the first wrote: one
        gpu::dispatch(ctx(), cmd, pass, 1, {{"ray_count", &b[4]}, {"group_counts", &b[1]}});
        count();  // writes what the third read: one (write after read)
        gpu::fill(ctx(), cmd, b[4], 0u);
        count();  // a transfer writing what the fourth read: one
        gpu::dispatch(ctx(), cmd, pass, 1, {{"ray_count", &b[4]}, {"group_counts", &b[0]}});
        count();  // reads what the fill wrote: one
    });
    EXPECT_EQ(after, (std::vector<uint64_t>{0, 0, 1, 2, 3, 4}));
    for (auto& buffer : b) gpu::destroy_buffer(ctx(), buffer);
}

TEST_F(BarrierTest, ASurfaceFrameRecordsFewerBarriersThanCommands) {
    // Before the tracking every dispatch and every group of fills ended in a full barrier.
    testing::CubeScene cube(ctx(), glm::vec3(0.15f), 6);
    for (SurfaceMethod method : {SurfaceMethod::adaptive, SurfaceMethod::uniform}) {
        SurfaceSettings settings;
        settings.method = method;
        const gpu::BarrierTracker& t = ctx().tracker();
        const uint64_t barriers = t.barriers(), commands = t.commands();
        cube.render(settings);
        const uint64_t b = t.barriers() - barriers, c = t.commands() - commands;
        std::printf("%s frame: %llu barriers for %llu commands\n",
                    method == SurfaceMethod::adaptive ? "adaptive" : "uniform", (unsigned long long)b,
                    (unsigned long long)c);
        EXPECT_GT(b, 0u);
        EXPECT_LT(b, c);
    }
}

}  // namespace
}  // namespace aquaform
