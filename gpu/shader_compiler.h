// GLSL compiled to SPIR-V at run time with glslang, the same compiler and target (Vulkan 1.2)
// the build uses, so that a viewer can reload a shader edited while it runs. Includes resolve
// against the including file's folder, then against the shader root (shaders/).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/result.h"

namespace aquaform::gpu {

/// Compiles the compute, vertex or fragment shader `file` (by extension); the error holds
/// glslang's messages, each with file and line.
Result<std::vector<uint32_t>> compile_glsl(const std::filesystem::path& file, const std::filesystem::path& root);

/// Watches a shader tree for edits. poll() recompiles the shaders whose sources or includes
/// changed since the last poll and installs them as overrides of the embedded ones
/// (gpu/shader_registry.h), so that passes created afterwards use them.
class ShaderWatcher {
public:
    explicit ShaderWatcher(std::filesystem::path root);
    struct Reload {
        std::vector<std::string> reloaded;  ///< shader names now overridden
        std::vector<std::string> errors;    ///< one per shader that failed (its old code stays)
    };
    Reload poll();
    const std::filesystem::path& root() const { return root_; }

private:
    std::map<std::filesystem::path, std::filesystem::file_time_type> stamps_;
    std::filesystem::path root_;
};

}  // namespace aquaform::gpu
