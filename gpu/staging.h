// Batched staging uploads, structured after nvpro_core2's nvvk::StagingUploader: host data is
// copied into host-visible chunks, a copy into the destination is recorded, and the chunks are
// recycled once the submission that reads them has completed (each thread's Context recorder
// owns one pool; a submission seals the chunks it staged into with its serial, and they return
// to the pool when the context has seen that submission's fence signal, so a submission still in
// flight never has its staging memory overwritten by a later one's).
// - Inside a recording (Context::submit on the same thread) an upload records into that
//   command buffer between barriers, so it lands in order with the passes around it. Small ones
//   (up to 64 KiB, 4-byte aligned: parameter blocks) go inline with vkCmdUpdateBuffer, needing no
//   staging memory at all.
// - Outside a recording an upload submits at once, unless an UploadBatch is open on the thread:
//   then its copy is held and recorded at the start of the thread's next submission, or when the
//   batch closes, so that many uploads share one submission.
// Downloads (device to host) are here too, beside the uploads: both record copies through the
// thread's recording and staging memory, which gpu/buffer.h (a module this one is built on)
// could reach only through an include cycle.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/context.h"

namespace aquaform::gpu {

/// The calling thread's staging memory, the SubmissionMemory its context keeps for it.
class StagingPool final : public SubmissionMemory {
public:
    struct Region {
        VkBuffer buffer = VK_NULL_HANDLE;
        VkDeviceSize offset = 0;
        void* mapped = nullptr;
    };
    /// Host-visible memory for `bytes`, in a chunk no submission in flight reads, valid until
    /// the submission that seals it has completed.
    Region allocate(Context& ctx, VkDeviceSize bytes);
    /// Holds a copy from a region until record_pending() (an open UploadBatch).
    void defer(const Region& src, VkBuffer dst, VkDeviceSize dst_offset, VkDeviceSize bytes);
    bool has_pending() const { return !pending_.empty(); }
    void discard_pending();
    /// Records the held copies into `cmd` (with the barriers around them) and forgets them.
    void record_pending(VkCommandBuffer cmd) override;
    /// The chunks allocated from since the last seal belong to submission `serial`.
    void seal(uint64_t serial) override;
    /// Every submission up to serial `completed` has completed: their chunks are reused.
    void recycle(Context& ctx, uint64_t completed) override;
    void destroy(Context& ctx) override;
    VkDeviceSize bytes_in_use() const;

    int batch_depth = 0;  ///< open UploadBatch scopes on the owning thread

private:
    struct Chunk {
        Buffer buffer;
        VkDeviceSize used = 0;
        uint64_t serial = 0;  ///< the submission in flight that reads it; 0: open to allocate
    };
    struct Copy {
        VkBuffer src, dst;
        VkBufferCopy region;
    };
    std::vector<Chunk> chunks_;
    std::vector<Copy> pending_;
};

/// The calling thread's pool in `ctx`, made on first use.
StagingPool& staging_pool(Context& ctx);

/// While alive, uploads made on this thread outside a recording are held and submitted together
/// (at the thread's next submission, or by submit() / the destructor) instead of one submission
/// each. Destination buffers must outlive the batch.
class UploadBatch {
public:
    explicit UploadBatch(Context& ctx);
    ~UploadBatch() noexcept(false);
    UploadBatch(const UploadBatch&) = delete;
    UploadBatch& operator=(const UploadBatch&) = delete;
    /// Submits what is held (waits for it).
    void submit();

private:
    Context* ctx_;
};

/// Records a copy of host data into `dst` into `cmd`, which must be the calling thread's
/// recording (Context::recording()) unless the upload is small enough to go inline. Barriers
/// order it after earlier reads and writes of `dst` and before later ones.
void record_upload(Context& ctx, VkCommandBuffer cmd, Buffer& dst, const void* data, VkDeviceSize bytes,
                   VkDeviceSize offset = 0);

/// Copies host data into a device buffer through staging memory. Inside this thread's recording
/// it records the copy there (in order with the passes around it); inside an UploadBatch it
/// joins the batch's submission; otherwise it submits and waits.
void upload(Context& ctx, Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
/// Copies a device buffer back to the host (waits for completion).
void download(Context& ctx, const Buffer& src, void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
/// Records a copy of `bytes` of `src` from `offset` into the host-visible `dst`, readable by the
/// host (dst.mapped) once the submission has completed: a download kept in flight.
void record_download(Context& ctx, VkCommandBuffer cmd, const Buffer& src, const Buffer& dst, VkDeviceSize bytes,
                     VkDeviceSize offset = 0);

template <typename T>
std::vector<T> download_vector(Context& ctx, const Buffer& src, size_t count) {
    std::vector<T> out(count);
    if (count) download(ctx, src, out.data(), count * sizeof(T));
    return out;
}

}  // namespace aquaform::gpu
