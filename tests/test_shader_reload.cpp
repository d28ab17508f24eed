// Shader hot reload: glslang compiles the tree's GLSL at run time like the build does; a watched
// tree recompiles an edited shader and passes created afterwards run it; a shader that does not
// compile reports file and line and keeps the code that worked.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "gpu/shader_compiler.h"
#include "gpu/shader_registry.h"
#include "render/surface_renderer.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;

class ShaderReloadTest : public testing::GpuTest {
protected:
    void TearDown() override {
        gpu::clear_shader_overrides();
        testing::GpuTest::TearDown();
    }
};

const fs::path kShaders = fs::path(AQUAFORM_SOURCE_DIR) / "shaders";

void replace_in_file(const fs::path& file, const std::string& from, const std::string& to) {
    std::stringstream text;
    text << std::ifstream(file).rdbuf();
    std::string s = text.str();
    const size_t at = s.find(from);
    ASSERT_NE(at, std::string::npos) << from << " not in " << file;
    s.replace(at, from.size(), to);
    std::ofstream(file, std::ios::trunc) << s;
    // A later stamp than the watcher saw, whatever the file system's clock resolution.
    fs::last_write_time(file, fs::last_write_time(file) + std::chrono::seconds(2));
}

TEST_F(ShaderReloadTest, EveryEmbeddedShaderCompilesFromTheTreeAtRunTime) {
    size_t compiled = 0;
    for (const gpu::EmbeddedShader& embedded : gpu::embedded_shaders()) {
        auto spirv = gpu::compile_glsl(kShaders / std::string(embedded.name), kShaders);
        ASSERT_TRUE(spirv.ok()) << spirv.error();
        EXPECT_EQ(spirv.value().at(0), 0x07230203u) << embedded.name << ": SPIR-V magic";
        ++compiled;
    }
    EXPECT_GT(compiled, 40u);
}

TEST_F(ShaderReloadTest, EditedShaderIsReloadedAndBrokenOneKeepsTheOldCode) {
    const fs::path tree = fs::temp_directory_path() / ("aquaform_shaders_" + std::to_string(getpid()));
    fs::remove_all(tree);
    fs::copy(kShaders, tree, fs::copy_options::recursive);
    gpu::ShaderWatcher watcher(tree);
    EXPECT_TRUE(watcher.poll().reloaded.empty()) << "nothing changed yet";

    Scene scene = testing::scene_with({glm::vec3(0.0f), glm::vec3(0.4f)}, 0.02f);
    const glm::vec3 centre(0.2f);
    testing::DeviceParticles particles(ctx(), {glm::vec4(centre, 0.0f)});
    ViewCamera camera;
    camera.eye = centre + glm::vec3(0.0f, 0.0f, 0.5f);
    camera.target = centre;
    camera.fov_y_degrees = 6.0f;
    auto centre_pixel = [&] {
        SurfaceRenderer renderer(ctx(), scene.particle_domain(), 32, 32, 1);
        const SurfaceFrame frame = renderer.render({particles.buffer, 1}, camera, SurfaceSettings{});
        const uint8_t* p = &frame.color.rgba[(16 * 32 + 16) * 4];
        return std::array<uint8_t, 4>{p[0], p[1], p[2], p[3]};
    };
    const auto before = centre_pixel();

    replace_in_file(tree / "render/compose.comp",
                    "color[index] = pack_srgb(tank_view(params.eye.xyz, dir, h.w, water));",
                    "color[index] = 0xff0000ffu;  // pure red, opaque");
    const auto reload = watcher.poll();
    ASSERT_TRUE(reload.errors.empty()) << reload.errors.front();
    ASSERT_EQ(reload.reloaded, std::vector<std::string>{"render/compose.comp"});
    const auto red = centre_pixel();
    EXPECT_EQ(red, (std::array<uint8_t, 4>{255, 0, 0, 255})) << "the reloaded shader runs";
    EXPECT_NE(before, red);

    replace_in_file(tree / "render/compose.comp", "color[index] = 0xff0000ffu;", "color[index] = not_a_variable;");
    const auto broken = watcher.poll();
    ASSERT_EQ(broken.errors.size(), 1u);
    EXPECT_NE(broken.errors[0].find("compose.comp"), std::string::npos) << broken.errors[0];
    EXPECT_NE(broken.errors[0].find("not_a_variable"), std::string::npos) << broken.errors[0];
    EXPECT_EQ(centre_pixel(), red) << "a broken edit keeps the last code that compiled";
    fs::remove_all(tree);
}

}  // namespace
}  // namespace aquaform
