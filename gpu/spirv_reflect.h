// The descriptor bindings a SPIR-V module declares, read back from the module itself (after the
// approach of zeux/niagara's parseShader): binding numbers, names, and whether the shader only
// reads (NonWritable, GLSL `readonly`) or only writes (NonReadable, `writeonly`) each buffer.
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
    bool storage = true;      ///< storage buffer (else a uniform buffer)
    bool reads = true;        ///< false: NonReadable (`writeonly`)
    bool writes = true;       ///< false: NonWritable (`readonly`)
};

/// The module's buffer bindings, ordered by (set, binding). Throws aquaform::Failure when
/// `spirv` is not a SPIR-V module; `shader` names it in the message.
std::vector<ShaderBinding> reflect_bindings(std::span<const uint32_t> spirv, std::string_view shader);

}  // namespace aquaform::gpu
