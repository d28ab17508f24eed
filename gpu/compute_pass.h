// A compute pass: one shader, its pipeline, its layout (storage buffers bound by push
// descriptors) and its local size. The bindings are read back from the shader's SPIR-V
// (gpu/spirv_reflect.h): names, numbers, read-only / write-only. `dispatch` takes the buffers
// by those names and checks push-constant size and that every binding the shader declares is
// given exactly once, so a mismatch between C++ and GLSL fails loudly at the call, naming the
// shader and the binding, rather than silently on the GPU.
//
// Choice (issue 13, item 4): names read back from SPIR-V rather than one binding-index header
// per pass in shaders/shared: GLSL stays the one place a binding is declared, nothing is kept
// in step by hand, and the access (readonly / writeonly) comes with it for the barriers.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/spirv_reflect.h"

namespace aquaform::gpu {

class Context;

/// Workgroup size of the passes that do not ask for another one.
constexpr uint32_t kDefaultLocalSize = 128;

struct ComputePassDesc {
    std::string shader;                       ///< embedded shader name, e.g. "sim/predict.comp"
    uint32_t bindings = 0;                    ///< storage buffers the shader declares (checked; 0 = take the shader's)
    uint32_t push_bytes = 0;                  ///< push-constant block size (0 = none)
    uint32_t local_size = kDefaultLocalSize;  ///< workgroup size, fed to the shader's local_size_x_id = 0
    /// Specialization constants 1, 2, ... (constant_id = index + 1): choices fixed per pipeline,
    /// so that the compiler drops the code of the other choice.
    std::vector<uint32_t> constants = {};
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
    /// The shader's bindings, by binding number.
    const std::vector<ShaderBinding>& bindings() const { return bindings_; }

private:
    void destroy();
    Context* ctx_ = nullptr;
    ComputePassDesc desc_;
    std::vector<ShaderBinding> bindings_;
    VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
};

/// One buffer for the shader's binding `name` (its GLSL instance or only member name).
struct Binding {
    std::string_view name;
    const Buffer* buffer;
};
using Bindings = std::initializer_list<Binding>;
/// Bindings built in pieces (a grid's neighbour lists and a pass's own: NeighborGrid's with_lists).
using BindingList = std::vector<Binding>;

/// Records `threads` invocations of `pass` (rounded up to whole workgroups; the shader checks
/// its own bound). In the calling thread's recording a barrier goes before it only where it
/// depends on an earlier command (gpu/barriers.h: it reads or writes a buffer written since the
/// last barrier, or writes one read since); in any other command buffer a full barrier follows.
void dispatch_raw(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, uint32_t threads, const void* push,
                  uint32_t push_bytes, std::span<const Binding> bindings);

template <typename Push>
void dispatch(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, uint32_t threads, const Push& push,
              Bindings bindings) {
    dispatch_raw(ctx, cmd, pass, threads, &push, sizeof(Push), std::span(bindings.begin(), bindings.size()));
}

template <typename Push>
void dispatch(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, uint32_t threads, const Push& push,
              const BindingList& bindings) {
    dispatch_raw(ctx, cmd, pass, threads, &push, sizeof(Push), bindings);
}

/// For passes without push constants.
inline void dispatch(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, uint32_t threads, Bindings bindings) {
    dispatch_raw(ctx, cmd, pass, threads, nullptr, 0, std::span(bindings.begin(), bindings.size()));
}

/// Records a dispatch whose workgroup counts (uint x, y, z at offset 0) an earlier pass wrote
/// into `group_counts`, followed by the same barrier as dispatch().
void dispatch_indirect(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const Buffer& group_counts,
                       Bindings bindings);
void dispatch_indirect_raw(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const Buffer& group_counts,
                           const void* push, uint32_t push_bytes, std::span<const Binding> bindings);

template <typename Push>
void dispatch_indirect(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const Buffer& group_counts,
                       const Push& push, Bindings bindings) {
    dispatch_indirect_raw(ctx, cmd, pass, group_counts, &push, sizeof(Push),
                          std::span(bindings.begin(), bindings.size()));
}

/// Transfers between passes, ordered by the same per-buffer tracking as dispatches.
void fill(Context& ctx, VkCommandBuffer cmd, const Buffer& buffer, uint32_t value, VkDeviceSize bytes = VK_WHOLE_SIZE);
void copy(Context& ctx, VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, const VkBufferCopy& region);

}  // namespace aquaform::gpu
