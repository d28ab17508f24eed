#include "gpu/compute_pass.h"

#include <stdexcept>
#include <utility>
#include <vector>

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/context.h"
#include "gpu/shader_registry.h"
#include "gpu/vk_check.h"

namespace aquaform::gpu {

namespace {

/// The view format of a storage texel buffer from its SPIR-V image format.
VkFormat texel_vk_format(const ShaderBinding& b, const std::string& shader) {
    switch (b.texel_format) {
        case 1:
            return VK_FORMAT_R32G32B32A32_SFLOAT;
        case 3:
            return VK_FORMAT_R32_SFLOAT;
        case 6:
            return VK_FORMAT_R32G32_SFLOAT;
        case 24:
            return VK_FORMAT_R32_SINT;
        case 30:
            return VK_FORMAT_R32G32B32A32_UINT;
        case 33:
            return VK_FORMAT_R32_UINT;
        case 35:
            return VK_FORMAT_R32G32_UINT;
        default:
            throw internal_failure(shader + ": texel buffer '" + b.name + "' has image format " +
                                   std::to_string(b.texel_format) +
                                   "; use rgba32f, rg32f, r32f, rgba32ui, rg32ui, r32ui or r32i");
    }
}

VkDescriptorType descriptor_type(const ShaderBinding& b) {
    if (!b.storage) return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    return b.texel_format ? VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}

}  // namespace

ComputePass::ComputePass(Context& ctx, const ComputePassDesc& desc)
    : ctx_(&ctx), desc_(desc), bindings_(reflect_bindings(find_shader(desc.shader), desc.shader)) {
    for (const ShaderBinding& b : bindings_) {
        if (b.set != 0) throw internal_failure(desc.shader + ": binding '" + b.name + "' must be in descriptor set 0");
        if (b.texel_format) texel_vk_format(b, desc.shader);  // a format the pass can view
    }
    if (desc.bindings != 0 && desc.bindings != bindings_.size())
        throw internal_failure(desc.shader + ": the pass expects " + std::to_string(desc.bindings) +
                               " bindings, the shader declares " + std::to_string(bindings_.size()));
    desc_.bindings = uint32_t(bindings_.size());
    std::vector<VkDescriptorSetLayoutBinding> bindings(bindings_.size());
    for (size_t i = 0; i < bindings_.size(); ++i) {
        bindings[i].binding = bindings_[i].binding;
        bindings[i].descriptorType = descriptor_type(bindings_[i]);
        bindings[i].descriptorCount = 1;
        bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    set_info.bindingCount = uint32_t(bindings.size());
    set_info.pBindings = bindings.data();
    VK_CHECK(vkCreateDescriptorSetLayout(ctx.device(), &set_info, nullptr, &set_layout_));
    ctx.set_name(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, set_layout_, desc.shader);

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, desc.push_bytes};
    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout_;
    layout_info.pushConstantRangeCount = desc.push_bytes ? 1 : 0;
    layout_info.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(ctx.device(), &layout_info, nullptr, &layout_));
    ctx.set_name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, layout_, desc.shader);

    VkShaderModule module = create_shader_module(ctx, desc.shader);
    std::vector<uint32_t> values{desc_.local_size};
    values.insert(values.end(), desc_.constants.begin(), desc_.constants.end());
    std::vector<VkSpecializationMapEntry> entries;
    for (uint32_t i = 0; i < values.size(); ++i)
        entries.push_back({i, i * uint32_t(sizeof(uint32_t)), sizeof(uint32_t)});
    VkSpecializationInfo spec{uint32_t(entries.size()), entries.data(), values.size() * sizeof(uint32_t),
                              values.data()};
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module;
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = &spec;
    info.layout = layout_;
    VkResult r = vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
    vkDestroyShaderModule(ctx.device(), module, nullptr);
    VK_CHECK(r);
    ctx.set_name(VK_OBJECT_TYPE_PIPELINE, pipeline_, desc.shader);
}

ComputePass::~ComputePass() { destroy(); }

ComputePass::ComputePass(ComputePass&& o) noexcept { *this = std::move(o); }

ComputePass& ComputePass::operator=(ComputePass&& o) noexcept {
    if (this != &o) {
        destroy();
        ctx_ = std::exchange(o.ctx_, nullptr);
        desc_ = o.desc_;
        bindings_ = std::move(o.bindings_);
        set_layout_ = std::exchange(o.set_layout_, VK_NULL_HANDLE);
        layout_ = std::exchange(o.layout_, VK_NULL_HANDLE);
        pipeline_ = std::exchange(o.pipeline_, VK_NULL_HANDLE);
    }
    return *this;
}

void ComputePass::destroy() {
    if (!ctx_) return;
    VkDevice d = ctx_->device();
    if (pipeline_) vkDestroyPipeline(d, pipeline_, nullptr);
    if (layout_) vkDestroyPipelineLayout(d, layout_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(d, set_layout_, nullptr);
    pipeline_ = VK_NULL_HANDLE;
    layout_ = VK_NULL_HANDLE;
    set_layout_ = VK_NULL_HANDLE;
    ctx_ = nullptr;
}

namespace {

std::string declared(const ComputePass& pass) {
    std::string names;
    for (const ShaderBinding& b : pass.bindings()) names += (names.empty() ? "" : ", ") + b.name;
    return names;
}

/// A dispatch labelled with its shader's name (its barrier and bindings included), so that a
/// validation message or a debugger's capture says which pass it is.
class DispatchLabel {
public:
    DispatchLabel(Context& ctx, VkCommandBuffer cmd, const std::string& shader) : ctx_(ctx), cmd_(cmd) {
        ctx_.begin_label(cmd_, shader);
    }
    ~DispatchLabel() { ctx_.end_label(cmd_); }
    DispatchLabel(const DispatchLabel&) = delete;
    DispatchLabel& operator=(const DispatchLabel&) = delete;

private:
    Context& ctx_;
    VkCommandBuffer cmd_;
};

/// The calling thread's barrier tracker when `cmd` is its recording, else null (commands then
/// get a full barrier after each, as in any command buffer the tracking does not know).
BarrierTracker* tracker_for(Context& ctx, VkCommandBuffer cmd) {
    return cmd == ctx.recording() ? &ctx.tracker() : nullptr;
}

/// Checks the push-constant size and that every binding is given once by its name, then binds
/// the pipeline, the buffers and the push constants; with a tracker, first records the barrier
/// the dispatch needs (its reads and writes from the shader's access, plus `indirect`).
void bind_pass(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const void* push, uint32_t push_bytes,
               std::span<const Binding> bindings, BarrierTracker* tracker, const Buffer* indirect = nullptr) {
    const ComputePassDesc& d = pass.desc();
    if (push_bytes != d.push_bytes)
        throw internal_failure(d.shader + ": push constants of " + std::to_string(push_bytes) +
                               " bytes given, the pass declares " + std::to_string(d.push_bytes));
    const std::vector<ShaderBinding>& declared_bindings = pass.bindings();
    std::vector<const Buffer*> by_index(declared_bindings.size(), nullptr);
    for (const Binding& given : bindings) {
        size_t i = 0;
        while (i < declared_bindings.size() && declared_bindings[i].name != given.name) ++i;
        if (i == declared_bindings.size())
            throw internal_failure(d.shader + ": no binding named '" + std::string(given.name) +
                                   "'; the shader declares: " + declared(pass));
        if (by_index[i]) throw internal_failure(d.shader + ": binding '" + std::string(given.name) + "' given twice");
        if (!given.buffer || !given.buffer->buffer)
            throw internal_failure(d.shader + ": binding '" + std::string(given.name) + "' given no buffer");
        by_index[i] = given.buffer;
    }
    for (size_t i = 0; i < by_index.size(); ++i)
        if (!by_index[i])
            throw internal_failure(d.shader + ": binding '" + declared_bindings[i].name + "' (binding " +
                                   std::to_string(declared_bindings[i].binding) + ") is not given");
    if (tracker) {
        std::vector<VkBuffer> reads, writes;
        for (size_t i = 0; i < by_index.size(); ++i) {
            if (declared_bindings[i].reads) reads.push_back(by_index[i]->buffer);
            if (declared_bindings[i].writes) writes.push_back(by_index[i]->buffer);
        }
        if (indirect) reads.push_back(indirect->buffer);
        tracker->access(cmd, reads.data(), reads.size(), writes.data(), writes.size());
    }
    std::vector<VkDescriptorBufferInfo> infos(by_index.size());
    std::vector<VkBufferView> views(by_index.size(), VK_NULL_HANDLE);
    std::vector<VkWriteDescriptorSet> writes(by_index.size());
    for (uint32_t i = 0; i < writes.size(); ++i) {
        const ShaderBinding& declared_binding = declared_bindings[i];
        writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        writes[i].dstBinding = declared_binding.binding;
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = descriptor_type(declared_binding);
        if (declared_binding.texel_format) {
            views[i] = texel_view(ctx, *by_index[i], texel_vk_format(declared_binding, d.shader));
            writes[i].pTexelBufferView = &views[i];
        } else {
            if (declared_binding.storage &&
                (by_index[i]->texels_only || by_index[i]->size > ctx.info().max_storage_buffer_bytes))
                throw internal_failure(d.shader + ": storage buffer '" + declared_binding.name + "' bound to buffer '" +
                                       by_index[i]->name + "' of " + std::to_string(by_index[i]->size) +
                                       " bytes, made for texels only or larger than the device's storage-buffer range");
            if (!declared_binding.storage && by_index[i]->size > ctx.limits().maxUniformBufferRange)
                throw internal_failure(d.shader + ": uniform block '" + declared_binding.name + "' bound to buffer '" +
                                       by_index[i]->name + "' of " + std::to_string(by_index[i]->size) +
                                       " bytes, more than the device's uniform-buffer range");
            infos[i] = {by_index[i]->buffer, 0, VK_WHOLE_SIZE};
            writes[i].pBufferInfo = &infos[i];
        }
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pass.pipeline());
    if (!writes.empty())
        ctx.push_descriptor_fn()(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pass.layout(), 0,
                                 static_cast<uint32_t>(writes.size()), writes.data());
    if (push_bytes) vkCmdPushConstants(cmd, pass.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes, push);
}

}  // namespace

void dispatch_raw(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, uint32_t threads, const void* push,
                  uint32_t push_bytes, std::span<const Binding> bindings) {
    if (threads == 0) return bind_pass(ctx, cmd, pass, push, push_bytes, bindings, nullptr);  // checks only
    ctx.command_boundary(cmd);
    const ComputePassDesc& d = pass.desc();
    BarrierTracker* tracker = tracker_for(ctx, cmd);
    DispatchLabel label(ctx, cmd, d.shader);
    bind_pass(ctx, cmd, pass, push, push_bytes, bindings, tracker);
    const uint32_t groups = (threads + d.local_size - 1) / d.local_size;
    const uint32_t max_x = ctx.limits().maxComputeWorkGroupCount[0];
    if (groups > max_x)
        throw internal_failure(d.shader + ": " + std::to_string(groups) + " workgroups exceed the device limit");
    vkCmdDispatch(cmd, groups, 1, 1);
    if (!tracker) compute_barrier(cmd);
}

void dispatch_indirect(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const Buffer& group_counts,
                       Bindings bindings) {
    dispatch_indirect_raw(ctx, cmd, pass, group_counts, nullptr, 0, std::span(bindings.begin(), bindings.size()));
}

void dispatch_indirect_raw(Context& ctx, VkCommandBuffer cmd, const ComputePass& pass, const Buffer& group_counts,
                           const void* push, uint32_t push_bytes, std::span<const Binding> bindings) {
    ctx.command_boundary(cmd);
    BarrierTracker* tracker = tracker_for(ctx, cmd);
    DispatchLabel label(ctx, cmd, pass.desc().shader);
    bind_pass(ctx, cmd, pass, push, push_bytes, bindings, tracker, &group_counts);
    vkCmdDispatchIndirect(cmd, group_counts.buffer, 0);
    if (!tracker) compute_barrier(cmd);
}

void fill(Context& ctx, VkCommandBuffer cmd, const Buffer& buffer, uint32_t value, VkDeviceSize bytes) {
    ctx.command_boundary(cmd);
    BarrierTracker* tracker = tracker_for(ctx, cmd);
    if (tracker) tracker->access(cmd, {}, {buffer.buffer});
    vkCmdFillBuffer(cmd, buffer.buffer, 0, bytes, value);
    if (!tracker) compute_barrier(cmd);
}

void copy(Context& ctx, VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, const VkBufferCopy& region) {
    ctx.command_boundary(cmd);
    BarrierTracker* tracker = tracker_for(ctx, cmd);
    if (tracker) tracker->access(cmd, {src.buffer}, {dst.buffer});
    vkCmdCopyBuffer(cmd, src.buffer, dst.buffer, 1, &region);
    if (!tracker) compute_barrier(cmd);
}

}  // namespace aquaform::gpu
