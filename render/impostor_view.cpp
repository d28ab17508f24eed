#include "render/impostor_view.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/image.h"
#include "gpu/shader_registry.h"
#include "gpu/vk_check.h"
#include "shaders/shared/render/impostor_layout.h"

namespace aquaform {

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr float kFloorAlbedo = 0.45f;
constexpr float kBoxAlbedo = 0.88f;
constexpr uint32_t kModeCount = 4;

glm::vec4 with_w(const glm::vec3& v, float w) { return glm::vec4(v, w); }

}  // namespace

struct ImpostorView::Impl {
    gpu::Image2D color, depth;
    gpu::Buffer readback;  ///< host-visible copy of the colour image, tightly packed rows
    gpu::Buffer dummy;     ///< bound when there are no particles (every draw shares the layout)
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipelines[kModeCount] = {};

    void destroy(gpu::Context& ctx) {
        VkDevice d = ctx.device();
        for (VkPipeline& p : pipelines) {
            if (p) vkDestroyPipeline(d, p, nullptr);
            p = VK_NULL_HANDLE;
        }
        if (layout) vkDestroyPipelineLayout(d, layout, nullptr);
        if (set_layout) vkDestroyDescriptorSetLayout(d, set_layout, nullptr);
        layout = VK_NULL_HANDLE;
        set_layout = VK_NULL_HANDLE;
        gpu::destroy_buffer(ctx, readback);
        gpu::destroy_buffer(ctx, dummy);
        gpu::destroy_image(ctx, color);
        gpu::destroy_image(ctx, depth);
    }

    VkPipeline create_pipeline(gpu::Context& ctx, uint32_t mode, VkShaderModule vert, VkShaderModule frag);
};

VkPipeline ImpostorView::Impl::create_pipeline(gpu::Context& ctx, uint32_t mode, VkShaderModule vert,
                                               VkShaderModule frag) {
    VkSpecializationMapEntry entry{0, 0, sizeof(uint32_t)};
    VkSpecializationInfo spec{1, &entry, sizeof(uint32_t), &mode};
    VkPipelineShaderStageCreateInfo stages[2] = {};
    stages[0] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                 nullptr,
                 0,
                 VK_SHADER_STAGE_VERTEX_BIT,
                 vert,
                 "main",
                 &spec};
    stages[1] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                 nullptr,
                 0,
                 VK_SHADER_STAGE_FRAGMENT_BIT,
                 frag,
                 "main",
                 &spec};

    VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology =
        mode == IMPOSTOR_MODE_LINES ? VK_PRIMITIVE_TOPOLOGY_LINE_LIST : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;  // quads and box faces are seen from either side
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    // The sky is behind everything; lines are tested but not written, so fluid in front of a
    // back edge hides it while front edges stay on top.
    depth.depthTestEnable = mode != IMPOSTOR_MODE_SKY;
    depth.depthWriteEnable = mode == IMPOSTOR_MODE_SOLID || mode == IMPOSTOR_MODE_PARTICLES;
    depth.depthCompareOp = mode == IMPOSTOR_MODE_LINES ? VK_COMPARE_OP_LESS_OR_EQUAL : VK_COMPARE_OP_LESS;
    VkPipelineColorBlendAttachmentState blend_attachment{};
    blend_attachment.colorWriteMask =
        VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blend_attachment;
    const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamic_states;
    const VkFormat color_format = kColorFormat;
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachmentFormats = &color_format;
    rendering.depthAttachmentFormat = kDepthFormat;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = &rendering;
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertex_input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VK_CHECK(vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    return pipeline;
}

ImpostorView::ImpostorView(gpu::Context& ctx, uint32_t width, uint32_t height)
    : ctx_(&ctx), width_(width), height_(height), impl_(new Impl) {
    try {
        if (width == 0 || height == 0)
            throw Failure("impostor view of " + std::to_string(width) + "x" + std::to_string(height) +
                          " pixels; give a width and height of at least 1");
        const auto& lim = ctx.limits();
        if (width > lim.maxFramebufferWidth || height > lim.maxFramebufferHeight)
            throw Failure("impostor view of " + std::to_string(width) + "x" + std::to_string(height) +
                          " pixels exceeds the device's framebuffer limit of " +
                          std::to_string(lim.maxFramebufferWidth) + "x" + std::to_string(lim.maxFramebufferHeight) +
                          "; render a smaller image");
        VkFormatProperties depth_props{};
        vkGetPhysicalDeviceFormatProperties(ctx.physical_device(), kDepthFormat, &depth_props);
        if (!(depth_props.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT))
            throw gpu::VulkanError(VK_ERROR_FORMAT_NOT_SUPPORTED,
                                   ctx.info().name + " cannot render to a D32 depth image (impostor view)");

        Impl& m = *impl_;
        m.color = gpu::create_image(ctx, "impostor color", width, height, kColorFormat,
                                    VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                    VK_IMAGE_ASPECT_COLOR_BIT);
        m.depth = gpu::create_image(ctx, "impostor depth", width, height, kDepthFormat,
                                    VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
        m.readback =
            gpu::create_buffer(ctx, "impostor readback", VkDeviceSize(width) * height * 4, gpu::MemoryUse::host);
        m.dummy = gpu::create_buffer(ctx, "impostor empty particles", 16);

        VkDescriptorSetLayoutBinding bindings[2] = {};
        for (uint32_t i = 0; i < 2; ++i)
            bindings[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr};
        VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        set_info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
        set_info.bindingCount = 2;
        set_info.pBindings = bindings;
        VK_CHECK(vkCreateDescriptorSetLayout(ctx.device(), &set_info, nullptr, &m.set_layout));
        ctx.set_name(VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, m.set_layout, "render/impostor");
        VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                  sizeof(shader::ImpostorPush)};
        VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layout_info.setLayoutCount = 1;
        layout_info.pSetLayouts = &m.set_layout;
        layout_info.pushConstantRangeCount = 1;
        layout_info.pPushConstantRanges = &range;
        VK_CHECK(vkCreatePipelineLayout(ctx.device(), &layout_info, nullptr, &m.layout));
        ctx.set_name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, m.layout, "render/impostor");

        VkShaderModule vert = gpu::create_shader_module(ctx, "render/impostor.vert");
        VkShaderModule frag = VK_NULL_HANDLE;
        try {
            frag = gpu::create_shader_module(ctx, "render/impostor.frag");
            for (uint32_t mode = 0; mode < kModeCount; ++mode) {
                m.pipelines[mode] = m.create_pipeline(ctx, mode, vert, frag);
                ctx.set_name(VK_OBJECT_TYPE_PIPELINE, m.pipelines[mode],
                             "render/impostor mode " + std::to_string(mode));
            }
        } catch (...) {
            vkDestroyShaderModule(ctx.device(), vert, nullptr);
            if (frag) vkDestroyShaderModule(ctx.device(), frag, nullptr);
            throw;
        }
        vkDestroyShaderModule(ctx.device(), vert, nullptr);
        vkDestroyShaderModule(ctx.device(), frag, nullptr);
    } catch (...) {
        impl_->destroy(ctx);  // a constructor that throws runs no destructor
        delete impl_;
        throw;
    }
}

ImpostorView::~ImpostorView() {
    impl_->destroy(*ctx_);
    delete impl_;
}

Image ImpostorView::render(const gpu::Buffer& positions, const gpu::Buffer& velocities, uint32_t count,
                           const ViewCamera& camera, const ImpostorStyle& style, const Box& domain,
                           std::span<const Box> static_boxes) {
    ctx_->submit_and_wait(
        [&](VkCommandBuffer cmd) { record(cmd, positions, velocities, count, camera, style, domain, static_boxes); });
    return image();
}

void ImpostorView::record(VkCommandBuffer cmd, const gpu::Buffer& positions, const gpu::Buffer& velocities,
                          uint32_t count, const ViewCamera& camera, const ImpostorStyle& style, const Box& domain,
                          std::span<const Box> static_boxes) {
    Impl& m = *impl_;
    const VkDeviceSize need = VkDeviceSize(count) * sizeof(glm::vec4);
    if (count > 0) {
        for (const gpu::Buffer* b : {&positions, &velocities})
            if (!b->buffer || b->size < need)
                throw Failure("impostor view: buffer '" + b->name + "' holds " + std::to_string(b->size) +
                              " bytes but " + std::to_string(count) + " particles need " + std::to_string(need) +
                              " (one vec4 each); pass the particle count "
                              "that the buffers were made for");
        if (count > UINT32_MAX / 6)
            throw Failure("impostor view: " + std::to_string(count) + " particles exceed " +
                          std::to_string(UINT32_MAX / 6) + " (6 vertices each)");
    }
    if (!(style.radius > 0.0f) || !(style.speed_for_full_color > 0.0f))
        throw Failure("impostor view: radius and speed_for_full_color must be positive (got " +
                      std::to_string(style.radius) + " and " + std::to_string(style.speed_for_full_color) + ")");

    if (!(glm::length(camera.target - camera.eye) > 0.0f))
        throw Failure(
            "impostor view: the camera's eye and target coincide (or are not finite); "
            "place the eye away from the point it looks at");
    const float aspect = float(width_) / float(height_);
    const glm::vec3 up = camera_axes(camera)[1];
    shader::ImpostorPush push{};
    push.view_proj = view_projection(camera, aspect, domain);
    push.eye = with_w(camera.eye, style.radius);
    push.up = with_w(up, 1.0f / style.speed_for_full_color);

    const gpu::Buffer& pos = count > 0 ? positions : m.dummy;
    const gpu::Buffer& vel = count > 0 ? velocities : m.dummy;

    // The solver's compute passes may have written the particles earlier in this command buffer.
    const VkMemoryBarrier2 particles{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                                     nullptr,
                                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                                     VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                     VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT,
                                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT};
    const VkDependencyInfo particles_dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO, nullptr, 0, 1, &particles};
    vkCmdPipelineBarrier2(cmd, &particles_dep);
    // The previous render's copy read the colour image; its contents are not kept.
    gpu::image_barrier(cmd, m.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_COPY_BIT, 0,
                       VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    const VkPipelineStageFlags2 tests =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    gpu::image_barrier(cmd, m.depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, tests,
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED, tests,
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                       VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);

    VkRenderingAttachmentInfo color_att{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color_att.imageView = m.color.view;
    color_att.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color_att.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color_att.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color_att.clearValue.color = {{0.0f, 0.0f, 0.0f, 1.0f}};
    VkRenderingAttachmentInfo depth_att{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth_att.imageView = m.depth.view;
    depth_att.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth_att.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth_att.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth_att.clearValue.depthStencil = {1.0f, 0};
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, {width_, height_}};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color_att;
    rendering.pDepthAttachment = &depth_att;
    vkCmdBeginRendering(cmd, &rendering);

    VkViewport viewport{0.0f, 0.0f, float(width_), float(height_), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, {width_, height_}};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    // Every pipeline shares the layout, so one push of the descriptors serves all draws.
    VkDescriptorBufferInfo infos[2] = {{pos.buffer, 0, VK_WHOLE_SIZE}, {vel.buffer, 0, VK_WHOLE_SIZE}};
    VkWriteDescriptorSet writes[2] = {};
    for (uint32_t i = 0; i < 2; ++i) {
        writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        writes[i].dstBinding = i;
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[i].pBufferInfo = &infos[i];
    }
    ctx_->push_descriptor_fn()(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m.layout, 0, 2, writes);
    auto draw = [&](uint32_t mode, const Box& box, float albedo, uint32_t vertices, uint32_t first) {
        push.box_min = with_w(box.min, albedo);
        push.box_max = with_w(box.max, 0.0f);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m.pipelines[mode]);
        vkCmdPushConstants(cmd, m.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push,
                           &push);
        vkCmdDraw(cmd, vertices, 1, first, 0);
    };
    draw(IMPOSTOR_MODE_SKY, domain, 0.0f, 3, 0);
    draw(IMPOSTOR_MODE_SOLID, domain, kFloorAlbedo, 6, IMPOSTOR_FLOOR_FIRST);
    for (const Box& b : static_boxes) draw(IMPOSTOR_MODE_SOLID, b, kBoxAlbedo, 36, 0);
    if (count > 0) draw(IMPOSTOR_MODE_PARTICLES, domain, 0.0f, count * 6, 0);
    draw(IMPOSTOR_MODE_LINES, domain, 0.0f, 24, 0);  // last: front edges stay on top of the fluid
    vkCmdEndRendering(cmd);

    gpu::image_barrier(cmd, m.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                       VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {width_, height_, 1};
    vkCmdCopyImageToBuffer(cmd, m.color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, m.readback.buffer, 1, &region);
    // The host reads the copy after the fence wait; this makes the transfer write visible to it.
    VkBufferMemoryBarrier2 to_host{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
    to_host.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    to_host.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    to_host.dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT;
    to_host.dstAccessMask = VK_ACCESS_2_HOST_READ_BIT;
    to_host.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    to_host.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    to_host.buffer = m.readback.buffer;
    to_host.size = VK_WHOLE_SIZE;
    VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dep.bufferMemoryBarrierCount = 1;
    dep.pBufferMemoryBarriers = &to_host;
    vkCmdPipelineBarrier2(cmd, &dep);
}

Image ImpostorView::image() const {
    const Impl& m = *impl_;
    Image out;
    out.width = width_;
    out.height = height_;
    out.rgba.resize(size_t(width_) * height_ * 4);
    std::memcpy(out.rgba.data(), m.readback.mapped, out.rgba.size());
    return out;
}

}  // namespace aquaform
