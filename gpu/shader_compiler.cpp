#include "gpu/shader_compiler.h"

#include <fstream>
#include <iterator>
#include <memory>
#include <mutex>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include "gpu/shader_registry.h"

namespace aquaform::gpu {

namespace {

namespace fs = std::filesystem;

bool read_text(const fs::path& path, std::string* text) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    text->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return true;
}

/// "shared/x.h" from the including file's folder, else from the shader root.
class TreeIncluder final : public glslang::TShader::Includer {
public:
    explicit TreeIncluder(fs::path root) : root_(std::move(root)) {}
    IncludeResult* includeLocal(const char* name, const char* includer, size_t) override {
        for (const fs::path& dir : {fs::path(includer).parent_path(), root_}) {
            const fs::path candidate = (dir / name).lexically_normal();
            auto text = std::make_unique<std::string>();
            if (!read_text(candidate, text.get())) continue;
            auto* result = new IncludeResult(candidate.string(), text->data(), text->size(), text.get());
            text.release();
            return result;
        }
        return nullptr;
    }
    void releaseInclude(IncludeResult* result) override {
        if (!result) return;
        delete static_cast<std::string*>(result->userData);
        delete result;
    }

private:
    fs::path root_;
};

EShLanguage stage_of(const fs::path& file) {
    const std::string ext = file.extension().string();
    return ext == ".vert" ? EShLangVertex : ext == ".frag" ? EShLangFragment : EShLangCompute;
}

}  // namespace

Result<std::vector<uint32_t>> compile_glsl(const fs::path& file, const fs::path& root) {
    static std::once_flag initialised;
    std::call_once(initialised, [] { glslang::InitializeProcess(); });
    std::string source;
    if (!read_text(file, &source)) return Error{"cannot read shader " + file.string()};
    const EShLanguage stage = stage_of(file);
    glslang::TShader shader(stage);
    const char* text = source.c_str();
    const std::string name = file.string();
    const char* names[] = {name.c_str()};
    shader.setStringsWithLengthsAndNames(&text, nullptr, names, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, stage, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    TreeIncluder includer(root);
    const auto messages = EShMessages(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 460, false, messages, includer))
        return Error{"shader " + name + " does not compile:\n" + shader.getInfoLog()};
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages)) return Error{"shader " + name + " does not link:\n" + program.getInfoLog()};
    std::vector<uint32_t> spirv;
    glslang::GlslangToSpv(*program.getIntermediate(stage), spirv);
    return spirv;
}

ShaderWatcher::ShaderWatcher(fs::path root) : root_(std::move(root)) {
    std::error_code ec;
    for (const auto& entry : fs::recursive_directory_iterator(root_, ec))
        if (entry.is_regular_file()) stamps_[entry.path()] = entry.last_write_time();
}

ShaderWatcher::Reload ShaderWatcher::poll() {
    Reload out;
    std::error_code ec;
    bool include_changed = false;
    std::vector<fs::path> changed_shaders;
    for (const auto& entry : fs::recursive_directory_iterator(root_, ec)) {
        if (!entry.is_regular_file()) continue;
        const auto stamp = entry.last_write_time();
        auto& known = stamps_[entry.path()];
        if (known == stamp) continue;
        known = stamp;
        const std::string ext = entry.path().extension().string();
        if (ext == ".comp" || ext == ".vert" || ext == ".frag")
            changed_shaders.push_back(entry.path());
        else
            include_changed = true;  // a header or .glsl: recompile everything that may use it
    }
    if (include_changed) {
        changed_shaders.clear();
        for (const auto& entry : fs::recursive_directory_iterator(root_, ec)) {
            const std::string ext = entry.path().extension().string();
            if (ext == ".comp" || ext == ".vert" || ext == ".frag") changed_shaders.push_back(entry.path());
        }
    }
    for (const fs::path& file : changed_shaders) {
        auto spirv = compile_glsl(file, root_);
        if (!spirv) {
            out.errors.push_back(spirv.error());
            continue;
        }
        const std::string name = file.lexically_relative(root_).generic_string();
        set_shader_override(name, std::move(spirv.value()));
        out.reloaded.push_back(name);
    }
    return out;
}

}  // namespace aquaform::gpu
