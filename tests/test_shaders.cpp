// Every shader under shaders/ is compiled at build time; here each one is embedded, loads as
// a module that the validation layer accepts, and the registry refuses unknown names.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/shader_registry.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class ShaderTest : public testing::GpuTest {};

TEST_F(ShaderTest, EveryShaderFileIsEmbeddedAndValid) {
    std::set<std::string> on_disk;
    const std::filesystem::path root = std::filesystem::path(AQUAFORM_ASSETS_DIR).parent_path() / "shaders";
    for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
        const auto ext = e.path().extension();
        if (ext == ".comp" || ext == ".vert" || ext == ".frag")
            on_disk.insert(std::filesystem::relative(e.path(), root).generic_string());
    }
    std::set<std::string> embedded;
    for (const auto& s : gpu::embedded_shaders()) {
        embedded.insert(std::string(s.name));
        ASSERT_GT(s.spirv.size(), 5u) << s.name;
        EXPECT_EQ(s.spirv[0], 0x07230203u) << s.name << " is not SPIR-V";
        VkShaderModule module = gpu::create_shader_module(ctx(), s.name);
        EXPECT_NE(module, VK_NULL_HANDLE);
        vkDestroyShaderModule(ctx().device(), module, nullptr);
    }
    EXPECT_EQ(embedded, on_disk) << "rebuild: a shader on disk is not embedded, or a stale one is";
    EXPECT_GE(embedded.size(), 12u);
}

TEST(ShaderRegistry, UnknownNameListsTheKnownOnes) {
    try {
        gpu::find_shader("sim/no_such_shader.comp");
        FAIL() << "expected an exception";
    } catch (const Failure& e) {
        EXPECT_NE(std::string(e.what()).find("sim/pbf_lambda.comp"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace aquaform
