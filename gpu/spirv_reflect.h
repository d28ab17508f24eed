// The descriptor bindings a SPIR-V module declares, read back from the module itself (after the
// approach of zeux/niagara's parseShader): binding numbers, names, and whether the shader only
// reads (NonWritable, GLSL `readonly`) or only writes (NonReadable, `writeonly`) each buffer,
// and for a storage texel buffer (imageBuffer) the format its view must have.
// A binding's name is its GLSL instance name, or for a block without one (`buffer Sorted
// { vec4 sorted[]; };`, the house style) the name of its only member (`sorted`), else the
// block's type name. Bindings are named once, in GLSL; C++ passes them by those names.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace aquaform::gpu {

struct ShaderBinding {
    uint32_t set = 0;
    uint32_t binding = 0;
    std::string name;
    bool storage = true;  ///< storage buffer or storage texel buffer (else a uniform buffer)
    /// A storage texel buffer (`layout(rgba32f) uniform imageBuffer`): the SPIR-V image format
    /// of its elements (1 rgba32f, 3 r32f, 30 rgba32ui, 33 r32ui, ...); 0 for a buffer block.
    uint32_t texel_format = 0;
    bool reads = true;   ///< false: NonReadable (`writeonly`)
    bool writes = true;  ///< false: NonWritable (`readonly`)
};

/// The module's buffer bindings, ordered by (set, binding). Throws aquaform::Failure when
/// `spirv` is not a SPIR-V module; `shader` names it in the message.
std::vector<ShaderBinding> reflect_bindings(std::span<const uint32_t> spirv, std::string_view shader);

}  // namespace aquaform::gpu
