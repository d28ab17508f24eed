// SPIR-V of every shader, compiled from GLSL by glslang at build time and embedded in the
// binary (so the program runs from any directory). Names are paths under shaders/ without
// the extension's dot, e.g. "sim/predict.comp".
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

namespace aquaform::gpu {

struct EmbeddedShader {
    std::string_view name;
    std::span<const uint32_t> spirv;
};

/// Every embedded shader (for the test that builds a pipeline from each one).
std::span<const EmbeddedShader> embedded_shaders();
/// The SPIR-V for `name` (an override when one is set); throws with the list of known names if
/// there is none.
std::span<const uint32_t> find_shader(std::string_view name);

/// Replaces the embedded SPIR-V of `name` for passes created from now on (shader hot reload,
/// gpu/shader_compiler.h); clear_shader_overrides() returns to the embedded code.
void set_shader_override(std::string_view name, std::vector<uint32_t> spirv);
void clear_shader_overrides();

class Context;
/// A shader module for `name`; the caller destroys it once its pipeline exists.
VkShaderModule create_shader_module(Context& ctx, std::string_view name);

}  // namespace aquaform::gpu
