#include "gpu/shader_registry.h"

#include <map>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"

namespace aquaform::gpu {

namespace {
std::map<std::string, std::vector<uint32_t>, std::less<>>& overrides() {
    static std::map<std::string, std::vector<uint32_t>, std::less<>> table;
    return table;
}
}  // namespace

void set_shader_override(std::string_view name, std::vector<uint32_t> spirv) {
    overrides()[std::string(name)] = std::move(spirv);
}

void clear_shader_overrides() { overrides().clear(); }

std::span<const uint32_t> find_shader(std::string_view name) {
    if (auto it = overrides().find(name); it != overrides().end()) return it->second;
    for (const EmbeddedShader& s : embedded_shaders())
        if (s.name == name) return s.spirv;
    std::string known;
    for (const EmbeddedShader& s : embedded_shaders()) known += " " + std::string(s.name);
    throw Failure("no shader named '" + std::string(name) + "'; known:" + known);
}

VkShaderModule create_shader_module(Context& ctx, std::string_view name) {
    auto spirv = find_shader(name);
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = spirv.size_bytes();
    info.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    VK_CHECK(vkCreateShaderModule(ctx.device(), &info, nullptr, &module));
    ctx.set_name(VK_OBJECT_TYPE_SHADER_MODULE, module, std::string(name));
    return module;
}

}  // namespace aquaform::gpu
