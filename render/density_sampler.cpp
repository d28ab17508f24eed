#include "render/density_sampler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "core/error.h"
#include "gpu/barriers.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"
#include "shaders/shared/render/render_kernels.h"

namespace aquaform {

namespace {

constexpr uint32_t kBoundsWords = 8;

}  // namespace

DensitySampler::DensitySampler(gpu::Context& ctx, const ParticleDomain& domain, uint32_t max_particles,
                               const SurfaceSettings& field, float voxel_radii)
    : ctx_(&ctx), field_(field), domain_(domain), max_particles_(std::max(max_particles, 1u)), buffers_(ctx) {
    if (auto valid = validate(field); !valid) throw Failure(valid.error());
    if (!(voxel_radii >= 0.05f && voxel_radii <= 4.0f))
        throw Failure("surface mesh: a voxel of " + std::to_string(voxel_radii) +
                      " particle radii is out of range; use 0.05..4 particle radii");
    // The renderer's field and iso value (make_surface_params; a test checks that they agree).
    const float r = render_radius(field, domain);
    const float particle_radius = domain.particle_radius();
    const float voxel = voxel_radii * particle_radius;
    const float pad = r + voxel;
    params_.clip_min = glm::vec4(domain.bounds.min - pad, voxel);
    params_.clip_max = glm::vec4(domain.bounds.max + pad, pad);
    params_.radius = r;
    params_.inv_radius = 1.0f / r;
    params_.kernel_coeff = shader::cubic_coefficient(r);
    params_.volume = domain.particle_spacing * domain.particle_spacing * domain.particle_spacing;
    params_.iso = params_.volume * params_.kernel_coeff *
                  shader::cubic_shape(std::min(field.lone_radius * particle_radius / r, 1.0f));
    clip_samples_ = 1;
    for (int a = 0; a < 3; ++a)
        clip_samples_ *= uint64_t(std::ceil(double(params_.clip_max[a] - params_.clip_min[a]) / voxel)) +
                         2;  // + 1 for float rounding

    params_buf_ = &buffers_.add("mesh.params", sizeof(shader::MeshParams));
    bounds_ = &buffers_.add("mesh.bounds", kBoundsWords * 4);
    lattice_ = &buffers_.add("mesh.lattice", sizeof(shader::MeshLattice));
    lattice_host_ = &buffers_.add("mesh.lattice_readback", sizeof(shader::MeshLattice), gpu::MemoryUse::host);
    bounds_pass_ = gpu::ComputePass(ctx, {"render/mesh_bounds.comp", 3, 0, MESH_WORKGROUP});
    sample_groups_ = &buffers_.add("mesh.sample_groups", 16);
    lattice_pass_ = gpu::ComputePass(ctx, {"render/mesh_lattice.comp", 4, 0, 1});
    sample_pass_ =
        gpu::ComputePass(ctx, {"render/mesh_sample.comp", 8, sizeof(shader::MeshSamplePush), MESH_WORKGROUP});
    params_.anisotropic = field.surface == SurfaceKernel::anisotropic ? 1u : 0u;

    // A first guess: the lattice around a compact cube of the particles; reserve() grows it.
    const double side = std::cbrt(double(max_particles_)) * domain.particle_spacing + 2.0 * pad;
    const double per_axis = std::ceil(side / voxel) + 2.0;
    reserve(std::min<uint64_t>(clip_samples_, uint64_t(per_axis * per_axis * per_axis)));
}

DensitySampler::~DensitySampler() = default;

bool DensitySampler::reads_in_place() const {
    return shared_grid_ && shared_grid_->geometry().cell_size >= params_.radius;
}

uint64_t DensitySampler::sample_limit() const {
    const gpu::DeviceInfo& device = ctx_->info();
    const uint64_t scan_limit = uint64_t(device.max_workgroups_x) * gpu::kDefaultLocalSize - 1;
    const uint64_t range_limit = device.max_storage_buffer_bytes / 4 - 1;
    const uint64_t texel_limit = ctx_->limits().maxTexelBufferElements;  // the passes read phi as texels
    return std::min({scan_limit, range_limit, texel_limit, uint64_t(UINT32_MAX - 1)});
}

void DensitySampler::reserve(uint64_t samples) {
    samples = std::min(samples, clip_samples_);
    if (lattice_buffers_ && samples <= capacity_) return;
    if (samples > sample_limit()) {
        std::ostringstream text;
        text << "surface mesh: the fluid's lattice needs " << samples << " samples (a voxel of " << voxel()
             << " m), more than " << ctx_->info().name << " can scan or bind (" << sample_limit()
             << "); mesh fewer particles: a larger particle_spacing (or --particles N) coarsens the lattice with them";
        throw resource_failure(text.str());
    }
    lattice_buffers_.reset();
    lattice_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    values_ = &lattice_buffers_->add("mesh.values", samples * 4);
    capacity_ = uint32_t(samples);
}

void DensitySampler::record(VkCommandBuffer cmd, const gpu::Buffer& positions, uint32_t count, gpu::GpuTimer* timer,
                            uint32_t vertex_capacity, uint32_t triangle_capacity) {
    if (count > max_particles_)
        throw Failure("surface mesh: " + std::to_string(count) + " particles, but it was made for " +
                      std::to_string(max_particles_));
    if (positions.size < uint64_t(count) * 16)
        throw Failure("surface mesh: the positions buffer '" + positions.name + "' holds fewer than " +
                      std::to_string(count) + " vec4 positions");
    gpu::GpuScope scope(timer, cmd, "mesh_sample");
    const gpu::Buffer *order = &positions, *cell_rank, *cell_start, *particles = &positions, *shape = bounds_;
    GridGeometry geometry;
    bool use_order = false;
    if (reads_in_place()) {
        geometry = shared_grid_->geometry();
        cell_rank = &shared_grid_->cell_rank();
        cell_start = &shared_grid_->cell_start();
    } else {
        make_own_grid();
        own_grid_->build(cmd, positions, count, nullptr);
        geometry = own_geometry_;
        order = &own_grid_->order();
        cell_rank = &own_grid_->cell_rank();
        cell_start = &own_grid_->cell_start();
        use_order = true;
    }
    if (params_.anisotropic) {
        // The kernels, from the particles in their grid's order (a sorted copy where the grid is
        // the own one); the field is then summed over the kernels' own grid.
        const gpu::Buffer* sorted = &positions;
        make_kernels();
        const shader::SurfaceParams kernel_params = make_field_params(field_, domain_, geometry, count);
        gpu::record_upload(*ctx_, cmd, *kernel_params_, &kernel_params, sizeof(kernel_params));
        if (use_order) {
            gpu::dispatch(
                *ctx_, cmd, gather_pass_, std::max(count, 1u),
                {{"params", kernel_params_}, {"positions", &positions}, {"order", order}, {"sorted", sorted_copy_}});
            sorted = sorted_copy_;
        }
        kernels_->record_shapes(cmd, *kernel_params_, *sorted, *cell_rank, *cell_start, count);
        gpu::fill(*ctx_, cmd, *no_classes_, 0u);  // the kernels carry no classes here
        kernels_->record_kernels(cmd, *kernel_params_, *no_classes_, *no_classes_, count);
        geometry = own_geometry_;
        particles = &kernels_->centres();
        shape = &kernels_->shapes();
        cell_rank = &kernels_->cell_rank();
        cell_start = &kernels_->cell_start();
        use_order = false;
    }
    params_.grid_origin_cell = glm::vec4(geometry.origin, geometry.cell_size);
    params_.grid_dims = glm::uvec4(geometry.dims, geometry.cell_count());
    params_.particle_count = count;
    params_.capacity = capacity_;
    params_.use_order = use_order ? 1u : 0u;
    params_.vertex_capacity = vertex_capacity;
    params_.triangle_capacity = triangle_capacity;
    // A sample sums the field like a ray's evaluation: its worst case, the whole lattice the
    // buffers hold, is split into dispatches within the device's work budget.
    params_.sample_slices = ctx_->dispatch_slices(double(capacity_) * kFieldVisitsPerEvaluation);
    gpu::record_upload(*ctx_, cmd, *params_buf_, &params_, sizeof(params_));

    gpu::fill(*ctx_, cmd, *bounds_, MESH_EMPTY_KEY);
    gpu::dispatch(*ctx_, cmd, bounds_pass_, std::max(count, 1u),
                  {{"params", params_buf_}, {"positions", &positions}, {"bounds", bounds_}});
    gpu::dispatch(
        *ctx_, cmd, lattice_pass_, 1,
        {{"params", params_buf_}, {"bounds", bounds_}, {"lattice", lattice_}, {"sample_groups", sample_groups_}});
    for (uint32_t slice = 0; slice < params_.sample_slices; ++slice)
        gpu::dispatch_indirect(*ctx_, cmd, sample_pass_, *sample_groups_, shader::MeshSamplePush{slice, 0, 0, 0},
                               {{"params", params_buf_},
                                {"lattice", lattice_},
                                {"positions", particles},
                                {"order", order},
                                {"cell_rank", cell_rank},
                                {"cell_start", cell_start},
                                {"values", values_},
                                {"shape", shape}});
}

void DensitySampler::make_own_grid() {
    if (own_grid_) return;
    auto made = grid_for_domain(domain_.bounds.min, domain_.bounds.max, params_.radius);
    if (!made) throw resource_failure("surface mesh: " + made.error());
    own_geometry_ = made.value();
    own_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    own_grid_ = std::make_unique<NeighborGrid>(*ctx_, *own_buffers_, own_geometry_, max_particles_, "mesh.grid");
}

void DensitySampler::make_kernels() {
    if (kernels_) return;
    make_own_grid();  // its geometry (cells r over the domain) is the kernels' grid's
    kernel_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    kernel_params_ = &kernel_buffers_->add("mesh.kernel_params", sizeof(shader::SurfaceParams));
    sorted_copy_ = &kernel_buffers_->add("mesh.sorted", uint64_t(max_particles_) * 16);
    no_classes_ = &kernel_buffers_->add("mesh.no_classes", uint64_t(max_particles_) * 4);
    kernels_ = std::make_unique<SurfaceKernels>(*ctx_, *kernel_buffers_, own_geometry_, max_particles_, "mesh");
    gather_pass_ = gpu::ComputePass(*ctx_, {"render/gather.comp", 4});
}

void DensitySampler::record_readback(VkCommandBuffer cmd) {
    gpu::copy(*ctx_, cmd, *lattice_, *lattice_host_, {0, 0, sizeof(shader::MeshLattice)});
    gpu::host_read_barrier(cmd);
}

shader::MeshLattice DensitySampler::lattice() const {
    shader::MeshLattice lattice;
    std::memcpy(&lattice, lattice_host_->mapped, sizeof lattice);
    return lattice;
}

DensityVolume DensitySampler::sample_volume(const gpu::Buffer& positions, uint32_t count) {
    shader::MeshLattice lattice{};
    // Twice at most: the second time with buffers for the lattice the first one measured.
    for (int attempt = 0; attempt < 2; ++attempt) {
        ctx_->submit_and_wait([&](VkCommandBuffer cmd) {
            record(cmd, positions, count, nullptr);
            record_readback(cmd);
        });
        lattice = this->lattice();
        if (lattice.dims.w <= capacity_) break;
        reserve(std::max<uint64_t>(lattice.dims.w, std::min(uint64_t(lattice.dims.w) * 3 / 2, sample_limit())));
    }
    if (lattice.dims.w > capacity_)
        throw internal_failure("surface mesh: the lattice did not fit the buffers made for it");
    DensityVolume volume;
    volume.origin = glm::vec3(lattice.origin_voxel);
    volume.voxel = lattice.origin_voxel.w;
    volume.dims = glm::uvec3(lattice.dims);
    volume.iso = params_.iso;
    volume.values = gpu::download_vector<float>(*ctx_, *values_, lattice.dims.w);
    return volume;
}

std::vector<gpu::BufferReport> DensitySampler::memory_report() const {
    auto report = buffers_.report();
    for (const gpu::BufferSet* set : {lattice_buffers_.get(), own_buffers_.get(), kernel_buffers_.get()})
        if (set)
            for (auto& entry : set->report()) report.push_back(entry);
    if (kernels_)
        for (auto& entry : kernels_->kernel_memory_report()) report.push_back(entry);
    return report;
}

}  // namespace aquaform
