// A compute pass: one shader, its pipeline, its layout (storage buffers bound by push
// descriptors) and its local size. `dispatch` checks push-constant size and binding count, so
// a mismatch between C++ and GLSL fails loudly at the call rather than silently on the GPU.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"

namespace aquaform::gpu {

class Context;

/// Workgroup size of the passes that do not ask for another one.
constexpr uint32_t kDefaultLocalSize = 128;

struct ComputePassDesc {
    std::string shader;          ///< embedded shader name, e.g. "sim/predict.comp"
    uint32_t bindings = 0;       ///< storage buffers at bindings 0..bindings-1
    uint32_t push_bytes = 0;     ///< push-constant block size (0 = none)
    uint32_t local_size = kDefaultLocalSize;  ///< workgroup size, fed to the shader's local_size_x_id = 0
};

class ComputePass {
public:
    ComputePass() = default;
    ComputePass(Context& ctx, const ComputePassDesc& desc);
    ~ComputePass();
    ComputePass(ComputePass&& other) noexcept;
    ComputePass& operator=(ComputePass&& other) noexcept;
    ComputePass(const ComputePass&) = delete;
    ComputePass& operator=(const ComputePass&) = delete;

    const ComputePassDesc& desc() const { return desc_; }
    VkPipeline pipeline() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_; }

private:
    void destroy();
    Context* ctx_ = nullptr;
    ComputePassDesc desc_;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
};

/// Records `threads` invocations of `pass` (rounded up to whole workgroups; the shader checks
/// its own bound) followed by a barrier that makes its writes visible to the next pass.
void dispatch_raw(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, uint32_t threads,
                  const void* push, uint32_t push_bytes, std::initializer_list<const Buffer*> bindings);

template <typename Push>
void dispatch(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, uint32_t threads,
              const Push& push, std::initializer_list<const Buffer*> bindings) {
    dispatch_raw(ctx, cmd, pass, threads, &push, sizeof(Push), bindings);
}

/// For passes without push constants.
inline void dispatch(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, uint32_t threads,
                     std::initializer_list<const Buffer*> bindings) {
    dispatch_raw(ctx, cmd, pass, threads, nullptr, 0, bindings);
}

/// Records a dispatch whose workgroup counts (uint x, y, z at offset 0) an earlier pass wrote
/// into `group_counts`, followed by the same barrier as dispatch().
void dispatch_indirect(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const Buffer& group_counts,
                       std::initializer_list<const Buffer*> bindings);
void dispatch_indirect_raw(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const Buffer& group_counts,
                           const void* push, uint32_t push_bytes, std::initializer_list<const Buffer*> bindings);

template <typename Push>
void dispatch_indirect(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const Buffer& group_counts,
                       const Push& push, std::initializer_list<const Buffer*> bindings) {
    dispatch_indirect_raw(ctx, cmd, pass, group_counts, &push, sizeof(Push), bindings);
}

/// Full compute/transfer barrier, for transfer commands (fills, copies) between passes.
void compute_barrier(VkCommandBuffer cmd);

}  // namespace aquaform::gpu
