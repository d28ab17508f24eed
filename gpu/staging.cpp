#include "gpu/staging.h"

#include <algorithm>
#include <cstring>
#include <exception>
#include <memory>
#include <stdexcept>

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/compute_pass.h"
#include "gpu/context.h"

namespace aquaform::gpu {

namespace {

constexpr VkDeviceSize kChunkBytes = VkDeviceSize(1) << 20;
constexpr VkDeviceSize kAlign = 16;
constexpr VkDeviceSize kInlineBytes = 65536;  // vkCmdUpdateBuffer's limit
constexpr size_t kKeptChunks = 4;

}  // namespace

StagingPool& staging_pool(Context& ctx) {
    std::unique_ptr<SubmissionMemory>& memory = ctx.submission_memory();
    if (!memory) memory = std::make_unique<StagingPool>();
    return static_cast<StagingPool&>(*memory);  // this function is the only one that fills the slot
}

StagingPool::Region StagingPool::allocate(Context& ctx, VkDeviceSize bytes) {
    bytes = (bytes + kAlign - 1) / kAlign * kAlign;
    for (Chunk& c : chunks_)
        if (c.serial == 0 && c.buffer.size - c.used >= bytes) {
            Region r{c.buffer.buffer, c.used, static_cast<char*>(c.buffer.mapped) + c.used};
            c.used += bytes;
            return r;
        }
    chunks_.push_back({create_buffer(ctx, "staging", std::max(bytes, kChunkBytes), MemoryUse::host), bytes, 0});
    return {chunks_.back().buffer.buffer, 0, chunks_.back().buffer.mapped};
}

void StagingPool::defer(const Region& src, VkBuffer dst, VkDeviceSize dst_offset, VkDeviceSize bytes) {
    pending_.push_back({src.buffer, dst, {src.offset, dst_offset, bytes}});
}

void StagingPool::record_pending(VkCommandBuffer cmd) {
    if (pending_.empty()) return;
    barrier_before_transfer_write(cmd);
    for (const Copy& c : pending_) vkCmdCopyBuffer(cmd, c.src, c.dst, 1, &c.region);
    barrier_after_transfer_write(cmd);
    pending_.clear();
}

void StagingPool::discard_pending() { pending_.clear(); }

void StagingPool::seal(uint64_t serial) {
    // (Held copies were recorded at the start of this submission: their chunks are sealed too.)
    for (Chunk& c : chunks_)
        if (c.serial == 0 && c.used > 0) c.serial = serial;
}

void StagingPool::recycle(Context& ctx, uint64_t completed) {
    for (Chunk& c : chunks_)
        if (c.serial != 0 && c.serial <= completed) c.used = c.serial = 0;
    // Keep a few standard free chunks for the next frames; free oversized ones (one big upload).
    size_t kept = 0;
    for (size_t i = 0; i < chunks_.size();) {
        Chunk& c = chunks_[i];
        const bool free = c.serial == 0 && c.used == 0;
        if (free && (c.buffer.size > kChunkBytes || kept == kKeptChunks)) {
            destroy_buffer(ctx, c.buffer);
            chunks_.erase(chunks_.begin() + std::ptrdiff_t(i));
            continue;
        }
        kept += free;
        ++i;
    }
}

void StagingPool::destroy(Context& ctx) {
    for (Chunk& c : chunks_) destroy_buffer(ctx, c.buffer);
    chunks_.clear();
    pending_.clear();
}

VkDeviceSize StagingPool::bytes_in_use() const {
    VkDeviceSize total = 0;
    for (const Chunk& c : chunks_) total += c.used;
    return total;
}

UploadBatch::UploadBatch(Context& ctx) : ctx_(&ctx) { ++staging_pool(ctx).batch_depth; }

UploadBatch::~UploadBatch() noexcept(false) {
    StagingPool& pool = staging_pool(*ctx_);
    --pool.batch_depth;
    if (pool.batch_depth > 0) return;      // an outer batch submits
    if (std::uncaught_exceptions() > 0) {  // unwinding: the destinations may be gone
        pool.discard_pending();
        return;
    }
    if (pool.has_pending()) ctx_->submit_and_wait([](VkCommandBuffer) {});
}

void UploadBatch::submit() {
    if (staging_pool(*ctx_).has_pending()) ctx_->submit_and_wait([](VkCommandBuffer) {});
}

void record_upload(Context& ctx, VkCommandBuffer cmd, Buffer& dst, const void* data, VkDeviceSize bytes,
                   VkDeviceSize offset) {
    if (bytes == 0) return;
    if (offset + bytes > dst.size)
        throw internal_failure("upload of " + std::to_string(bytes) + " bytes at " + std::to_string(offset) +
                               " overruns buffer '" + dst.name + "' of " + std::to_string(dst.size) + " bytes");
    // In the thread's recording the tracker orders the write (gpu/barriers.h); elsewhere barriers
    // on both sides.
    BarrierTracker* tracker = cmd == ctx.recording() ? &ctx.tracker() : nullptr;
    if (tracker)
        tracker->access(cmd, {}, {dst.buffer});
    else
        barrier_before_transfer_write(cmd);
    if (bytes <= kInlineBytes && bytes % 4 == 0 && offset % 4 == 0) {
        vkCmdUpdateBuffer(cmd, dst.buffer, offset, bytes, data);
    } else {
        if (cmd != ctx.recording())
            throw internal_failure("gpu::record_upload: a staged upload into '" + dst.name +
                                   "' needs the calling thread's recording (Context::submit_and_wait)");
        StagingPool::Region src = staging_pool(ctx).allocate(ctx, bytes);
        std::memcpy(src.mapped, data, bytes);
        VkBufferCopy region{src.offset, offset, bytes};
        vkCmdCopyBuffer(cmd, src.buffer, dst.buffer, 1, &region);
    }
    if (!tracker) barrier_after_transfer_write(cmd);
}

void upload(Context& ctx, Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    if (bytes == 0) return;
    if (VkCommandBuffer cmd = ctx.recording()) {  // in order with the passes recorded around it
        record_upload(ctx, cmd, dst, data, bytes, offset);
        return;
    }
    StagingPool& pool = staging_pool(ctx);
    if (offset + bytes > dst.size)
        throw internal_failure("upload of " + std::to_string(bytes) + " bytes at " + std::to_string(offset) +
                               " overruns buffer '" + dst.name + "' of " + std::to_string(dst.size) + " bytes");
    StagingPool::Region src = pool.allocate(ctx, bytes);
    std::memcpy(src.mapped, data, bytes);
    pool.defer(src, dst.buffer, offset, bytes);
    if (pool.batch_depth == 0) ctx.submit_and_wait([](VkCommandBuffer) {});  // records the copy first
}

void download(Context& ctx, const Buffer& src, void* data, VkDeviceSize bytes, VkDeviceSize offset) {
    if (bytes == 0) return;
    Buffer staging = create_buffer(ctx, "staging", bytes, MemoryUse::host);
    ctx.submit_and_wait([&](VkCommandBuffer cmd) { record_download(ctx, cmd, src, staging, bytes, offset); });
    std::memcpy(data, staging.mapped, bytes);
    destroy_buffer(ctx, staging);
}

void record_download(Context& ctx, VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, VkDeviceSize bytes,
                     VkDeviceSize offset) {
    if (!dst.mapped || offset + bytes > src.size || bytes > dst.size)
        throw internal_failure("download of " + std::to_string(bytes) + " bytes at " + std::to_string(offset) +
                               " of '" + src.name + "' (" + std::to_string(src.size) + " bytes) into '" + dst.name +
                               "' (" + std::to_string(dst.size) +
                               (dst.mapped ? " bytes)" : " bytes, not host-visible)"));
    copy(ctx, cmd, src, dst, {offset, 0, bytes});
    host_read_barrier(cmd);
}

}  // namespace aquaform::gpu
