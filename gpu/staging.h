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
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/buffer.h"

namespace aquaform::gpu {

class Context;

class StagingPool {
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
    void record_pending(VkCommandBuffer cmd);
    /// The chunks allocated from since the last seal belong to submission `serial`.
    void seal(uint64_t serial);
    /// Every submission up to serial `completed` has completed: their chunks are reused.
    void recycle(Context& ctx, uint64_t completed);
    void destroy(Context& ctx);
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

}  // namespace aquaform::gpu
