// The Vulkan context: instance, the chosen physical device, one queue that does compute and
// graphics, a command pool per thread that submits, and validation-message accounting for tests.
// Threads may share a context: the queue is locked around each submission (lock_queue() for
// submissions made elsewhere, the viewer's frames), and each thread records into its own command
// buffers. A thread may keep a few submissions in flight (submit() and wait()): each has its own
// command buffer, fence and staging memory, so the host can prepare or consume one frame while
// the device runs the next.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <vulkan/vulkan.h>

namespace aquaform::gpu {

class BarrierTracker;
class Context;

/// Memory a thread's recordings hand to the device that must outlive their submissions: the
/// staging memory of uploads (gpu/staging.h's StagingPool, made on a thread's first upload). The
/// context keeps one per thread and tells it each step of a submission's life.
class SubmissionMemory {
public:
    virtual ~SubmissionMemory() = default;
    /// A recording begins in `cmd`: what is held for the next submission is recorded first.
    virtual void record_pending(VkCommandBuffer cmd) = 0;
    /// What was handed out since the last seal is read by submission `serial`.
    virtual void seal(uint64_t serial) = 0;
    /// Every submission of the thread up to `completed` has completed.
    virtual void recycle(Context& ctx, uint64_t completed) = 0;
    /// Frees everything (the context is being destroyed).
    virtual void destroy(Context& ctx) = 0;
};

struct DeviceInfo {
    uint32_t index = 0;
    std::string name;
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    uint32_t api_version = 0;
    uint64_t device_local_bytes = 0;  ///< size of the largest device-local heap
    uint64_t max_storage_buffer_bytes = 0;
    /// The largest buffer a storage texel buffer views: maxTexelBufferElements of the widest texel
    /// (16 B, rgba32). Buffers read and written only as texels (the neighbour lists) may exceed the
    /// storage-buffer range up to this (lavapipe: 128 MiB storage range, 2 GiB as texels).
    uint64_t max_texel_buffer_bytes = 0;
    uint32_t max_workgroups_x = 0;  ///< largest dispatch along x
    /// Lanes of a subgroup in compute shaders, where they can shuffle values among themselves;
    /// 1 where compute shaders have no subgroup shuffles.
    uint32_t subgroup_size = 1;
    VkDriverId driver_id = VkDriverId(0);  ///< VkPhysicalDeviceDriverProperties::driverID
    /// Quirk: loop iterations a shader invocation may run in total before the device silently
    /// ends its loops (0 = no such limit). Lavapipe (VK_DRIVER_ID_MESA_LLVMPIPE) has 65535; the
    /// passes that could exceed it split their work into resumable passes only where it is set.
    uint32_t loop_iteration_limit = 0;
    /// Quirk: the device is the CPU (the software device), so one submission of a simulation frame
    /// holds its one in-order queue for a long time: an interactive caller shares the queue
    /// (Context::QueueSharing) only here; on a GPU a frame's submission is short.
    bool slow_in_order_queue = false;
    /// Work one dispatch may hold, in particle visits (one candidate particle's distance test
    /// and kernel: the unit every long pass is made of). dispatch_work_budget() chooses it from
    /// the device's type; Context::dispatch_slices splits a pass that could exceed it.
    uint64_t dispatch_work_budget = 0;
    bool usable = false;  ///< has the queue, Vulkan 1.3 and extensions we need
    std::string unusable_reason;
};

const char* device_type_name(VkPhysicalDeviceType type);

/// Particle visits one dispatch may hold on a device of this type: what a slow device of the
/// type does in about a quarter of a second (floors assumed from the slowest Vulkan 1.3 devices
/// of each kind: discrete 2e10 visits/s, integrated and virtual 4e9, other 4e9), so that a
/// dispatch ends long before a display driver's watchdog (Windows: 2 s; NVIDIA on Linux with a
/// display: a few seconds) takes the device away (VK_ERROR_DEVICE_LOST). The software device has
/// no watchdog; its budget (the discrete one) bounds a dispatch to a few seconds there.
uint64_t dispatch_work_budget(VkPhysicalDeviceType type);

/// Dispatches a pass of `work` particle visits needs under `budget` (at least 1, at most 65535).
uint32_t slices_for_budget(double work, uint64_t budget);

/// A submission in flight (Context::submit): a ticket for Context::wait on the thread that made it.
struct Submission {
    uint64_t serial = 0;  ///< the thread's count of submissions at this one; 0: none
    std::thread::id thread;
};

/// Thrown by Context::yield_queue when the thread's cancel flag is set.
struct Cancelled : std::exception {
    const char* what() const noexcept override { return "cancelled at a queue yield"; }
};

struct ContextOptions {
    std::string device;       ///< "" = automatic; else an index or a case-insensitive name part
    bool validation = false;  ///< enable VK_LAYER_KHRONOS_validation and count its errors
    /// Presentation (the viewer): the instance extensions the window system needs, and a function
    /// that makes the window's surface once the instance exists. With it the context enables
    /// VK_KHR_swapchain, requires its queue to present to the surface, and destroys the surface
    /// before the instance.
    std::vector<std::string> instance_extensions;
    std::function<VkSurfaceKHR(VkInstance)> make_surface;
};

class Context {
public:
    explicit Context(const ContextOptions& options);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    /// Lists every Vulkan device without creating a logical device (for `aquaform info`).
    static std::vector<DeviceInfo> list_devices();
    /// The device automatic choice would take: discrete GPU, else any GPU, else the software
    /// device. Returns the index into `devices`, or -1 when none is usable.
    static int choose_device(const std::vector<DeviceInfo>& devices, const std::string& request, std::string* error);

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physical_device() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    VkSurfaceKHR surface() const { return surface_; }  ///< VK_NULL_HANDLE without presentation
    uint32_t queue_family() const { return queue_family_; }
    const DeviceInfo& info() const { return info_; }
    const VkPhysicalDeviceLimits& limits() const { return limits_; }
    float timestamp_period_ns() const { return limits_.timestampPeriod; }
    PFN_vkCmdPushDescriptorSetKHR push_descriptor_fn() const { return push_descriptor_; }

    uint32_t find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags wanted, VkMemoryPropertyFlags fallback) const;

    /// Debug names through VK_EXT_debug_utils, which the context enables whenever the loader
    /// offers it: validation messages and GPU debuggers then say "grid.neighbors" or
    /// "render_march" rather than a handle. Without the extension these do nothing.
    bool debug_names() const { return set_object_name_ != nullptr; }
    template <typename Handle>
    void set_name(VkObjectType type, Handle handle, const std::string& name) const {
        name_object(type, (uint64_t)handle, name);  // dispatchable handles are pointers, the others integers
    }
    /// A labelled region of `cmd` (a timed scope, a dispatch); regions nest.
    void begin_label(VkCommandBuffer cmd, const std::string& name) const;
    void end_label(VkCommandBuffer cmd) const;

    using Recording = std::function<void(VkCommandBuffer)>;
    /// Submissions a thread keeps in flight at most: submit() waits for the oldest beyond them.
    static constexpr uint32_t kInFlight = 3;

    /// Records commands with `record` into one of this thread's command buffers and submits them
    /// without waiting (the queue is held only while submitting). Memory the recording staged is
    /// reused only once the submission has completed. Host-visible results may be read after
    /// wait(); until then the buffers it uses must stay alive and unwritten by the host.
    Submission submit(const Recording& record);
    /// Returns once `s` and every earlier submission of this thread have completed (at once for
    /// those already waited for). Only on the thread that submitted.
    void wait(Submission s);
    /// Whether `s` has completed, without waiting.
    bool done(Submission s);
    /// submit() and wait().
    void submit_and_wait(const Recording& record) { wait(submit(record)); }
    /// The calling thread's command buffer while it records inside submit, else VK_NULL_HANDLE
    /// (gpu::upload records into it instead of submitting).
    VkCommandBuffer recording() {
        Recorder& r = recorder();
        return r.recording ? r.current->cmd : VK_NULL_HANDLE;
    }
    /// The calling thread's submission memory (gpu/staging.h fills it on first use); what a
    /// submission took is recycled once it completes.
    std::unique_ptr<SubmissionMemory>& submission_memory() { return recorder().memory; }
    /// The barrier state of the calling thread's command buffer (gpu/barriers.h).
    BarrierTracker& tracker() { return *recorder().tracker; }
    /// Test hook: pretends the device has (or lacks) the loop-iteration quirk.
    void override_loop_iteration_limit(uint32_t limit) { info_.loop_iteration_limit = limit; }
    /// Test hook: another per-dispatch work budget (DeviceInfo::dispatch_work_budget).
    void override_dispatch_work_budget(uint64_t visits) { info_.dispatch_work_budget = visits; }
    /// Submissions made so far, by every thread (for tests and the batching figures).
    uint64_t submissions() const { return submissions_.load(); }

    /// Sharing the queue: the one hook through which a caller (the viewer's worker) cuts its
    /// thread's long recordings into several submissions, so that another thread's work (the
    /// window's frames) is not queued behind a whole simulation frame on a device whose one queue
    /// runs submissions strictly in order (the software device). The solver and the renderers
    /// know nothing of it: the cut points are the starts of outermost timed scopes (GpuTimer) and,
    /// with no scope open, every command the gpu helpers record (dispatch, fill, copy). A long
    /// single pass may ask long_pass_slices() into how many dispatches to split itself.
    struct QueueSharing {
        bool enabled = false;
        uint32_t long_pass_slices = 4;              ///< slices of one long pass while enabled
        const std::atomic<bool>* cancel = nullptr;  ///< set: a cut throws Cancelled instead
    };
    /// Sets the calling thread's sharing. With `cancel`, a cut that finds it set throws Cancelled
    /// (the recording is ended, not submitted), so that a thread asked to stop leaves a long frame
    /// at its next cut.
    void share_queue(const QueueSharing& sharing);
    /// Whether the calling thread's recordings are cut.
    bool yielding() { return recorder().sharing.enabled; }
    /// Into how many dispatches a long pass splits itself on this thread: 1 unless sharing.
    uint32_t long_pass_slices() {
        const QueueSharing& s = recorder().sharing;
        return s.enabled ? std::max(s.long_pass_slices, 1u) : 1u;
    }
    /// Into how many dispatches a pass of `work` particle visits splits itself: enough to keep
    /// each within the device's work budget, and at least long_pass_slices().
    uint32_t dispatch_slices(double work) {
        return std::max(long_pass_slices(), slices_for_budget(work, info_.dispatch_work_budget));
    }
    /// A cut: with sharing on for this thread, the commands so far are submitted and waited for,
    /// and recording continues in `cmd` (this thread's command buffer inside submit, which is
    /// begun again); otherwise it does nothing. Only outside render passes.
    void yield_queue(VkCommandBuffer cmd);
    /// A cut point of the gpu helpers: a cut only while no timed scope is open on this thread
    /// (a scope's time would otherwise include the other threads' work).
    void command_boundary(VkCommandBuffer cmd) {
        if (recorder().open_scopes == 0) yield_queue(cmd);
    }
    /// Timed scopes open on this thread (GpuTimer keeps count).
    void enter_scope(VkCommandBuffer cmd) {
        command_boundary(cmd);
        ++recorder().open_scopes;
    }
    void leave_scope() {
        Recorder& r = recorder();
        if (r.open_scopes > 0) --r.open_scopes;
    }

    /// Held while calling vkQueueSubmit / vkQueuePresentKHR / vkQueueWaitIdle directly.
    std::unique_lock<std::mutex> lock_queue() { return std::unique_lock<std::mutex>(queue_mutex_); }
    /// Waits until the queue has finished everything submitted so far, by any thread (instead of
    /// vkDeviceWaitIdle, which would need every thread's queue access stopped).
    void wait_queue_idle();

    /// Validation errors reported since creation (or since the last reset). A message as kept and
    /// printed ends with the names of the objects it concerns and the labels of the command
    /// buffer's open regions, where the layer gives them.
    uint32_t validation_errors() const { return validation_errors_.load(); }
    std::string last_validation_message() const {
        std::lock_guard<std::mutex> lock(message_mutex_);
        return last_validation_message_;
    }
    void reset_validation_errors() { validation_errors_ = 0; }

private:
    /// A command buffer of a thread and the fence of its last submission.
    struct Slot {
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE;
        uint64_t serial = 0;  ///< of the submission in flight in it; 0: free
    };
    /// One thread's command buffers: a ring of kInFlight slots.
    struct Recorder {
        VkCommandPool pool = VK_NULL_HANDLE;
        Slot slots[kInFlight];
        Slot* current = nullptr;  ///< the slot being (or last) recorded
        uint64_t submitted = 0;   ///< serial of the thread's last submission
        QueueSharing sharing;
        uint32_t open_scopes = 0;
        bool recording = false;
        std::unique_ptr<SubmissionMemory> memory;
        std::unique_ptr<BarrierTracker> tracker;
    };
    Recorder& recorder();          ///< the calling thread's, made at its first use
    Slot& free_slot(Recorder& r);  ///< a slot to record into (waits for the oldest when all are busy)
    void begin(Recorder& r, Slot& slot);
    uint64_t flush(Recorder& r);  ///< ends and submits the recording; its serial
    void retire(Slot& slot);      ///< waits for a slot's submission and frees the slot
    void recycle(Recorder& r);    ///< staging of every completed submission back to the pool

    void create(const ContextOptions& options);
    void destroy();
    void name_object(VkObjectType type, uint64_t handle, const std::string& name) const;
    static VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                         VkDebugUtilsMessageTypeFlagsEXT types,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    uint32_t queue_family_ = 0;
    std::mutex queue_mutex_;
    std::mutex recorders_mutex_;
    std::map<std::thread::id, std::unique_ptr<Recorder>> recorders_;
    DeviceInfo info_;
    VkPhysicalDeviceLimits limits_{};
    VkPhysicalDeviceMemoryProperties memory_{};
    PFN_vkCmdPushDescriptorSetKHR push_descriptor_ = nullptr;
    PFN_vkSetDebugUtilsObjectNameEXT set_object_name_ = nullptr;
    PFN_vkCmdBeginDebugUtilsLabelEXT begin_label_ = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT end_label_ = nullptr;
    std::atomic<uint32_t> validation_errors_{0};
    std::atomic<uint64_t> submissions_{0};
    mutable std::mutex message_mutex_;
    std::string last_validation_message_;
};

}  // namespace aquaform::gpu
