#include "render/surface_mesher.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/timer.h"

namespace aquaform {

namespace {

/// Half again what was needed, within `limit` (and never below what was needed).
uint64_t grown(uint64_t needed, uint64_t limit) { return std::max(needed, std::min(needed * 3 / 2, limit)); }

}  // namespace

SurfaceMesher::SurfaceMesher(gpu::Context& ctx, const ParticleDomain& domain, uint32_t max_particles,
                             const SurfaceSettings& field, float voxel_radii)
    : ctx_(&ctx), sampler_(ctx, domain, max_particles, field, voxel_radii), buffers_(ctx) {
    const MarchingCubesTable& table = marching_cubes_table();
    table_ = &buffers_.add("mesh.table", sizeof(table));
    gpu::upload(ctx, *table_, table.data(), sizeof(table));
    classify_ = gpu::ComputePass(ctx, {"render/mesh_classify.comp", 6, 0, MESH_WORKGROUP});
    vertices_pass_ = gpu::ComputePass(ctx, {"render/mesh_vertices.comp", 6, 0, MESH_WORKGROUP});
    triangles_pass_ = gpu::ComputePass(ctx, {"render/mesh_triangles.comp", 7, 0, MESH_WORKGROUP});
    reserve_lattice(sampler_.capacity());
    // A first guess from the sampler's: the surface of a cube of its samples, about 8 vertices per
    // voxel face area, and twice as many triangles as vertices (a closed surface's Euler count).
    const double side = std::cbrt(double(sampler_.capacity()));
    reserve_output(uint64_t(8.0 * side * side), uint64_t(16.0 * side * side));
}

SurfaceMesher::~SurfaceMesher() = default;

void SurfaceMesher::reserve_lattice(uint64_t samples) {
    sampler_.reserve(samples);
    const uint64_t entries = uint64_t(sampler_.capacity()) + 1;  // + 1: the prefix sum's end is the total
    if (lattice_buffers_ && vertex_offset_->size >= entries * 4) return;
    scan_ = gpu::PrefixSum();
    lattice_buffers_.reset();
    lattice_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    vertex_offset_ = &lattice_buffers_->add("mesh.vertex_offset", entries * 4);
    triangle_offset_ = &lattice_buffers_->add("mesh.triangle_offset", entries * 4);
    scan_ = gpu::PrefixSum(*ctx_, *lattice_buffers_, uint32_t(entries), "mesh");
}

void SurfaceMesher::reserve_output(uint64_t vertices, uint64_t triangles) {
    vertices = std::max<uint64_t>(vertices, 64);
    triangles = std::max<uint64_t>(triangles, 64);
    if (output_buffers_ && vertices <= vertex_capacity_ && triangles <= triangle_capacity_) return;
    vertices = std::max<uint64_t>(vertices, vertex_capacity_);
    triangles = std::max<uint64_t>(triangles, triangle_capacity_);
    const uint64_t limit = std::min<uint64_t>(ctx_->info().max_storage_buffer_bytes / 12, UINT32_MAX);
    if (vertices > limit || triangles > limit) {
        std::ostringstream text;
        text << "surface mesh: " << vertices << " vertices and " << triangles << " triangles need more than "
             << ctx_->info().name << " binds in one buffer (" << limit << " of each, 12 bytes apiece); mesh fewer "
             << "particles: a larger particle_spacing (or --particles N) coarsens the lattice with them";
        throw resource_failure(text.str());
    }
    output_buffers_.reset();
    output_buffers_ = std::make_unique<gpu::BufferSet>(*ctx_);
    // Host-visible: the mesh is read where the passes wrote it.
    vertices_ = &output_buffers_->add("mesh.vertices", vertices * 12, gpu::MemoryUse::host);
    normals_ = &output_buffers_->add("mesh.normals", vertices * 12, gpu::MemoryUse::host);
    triangles_ = &output_buffers_->add("mesh.triangles", triangles * 12, gpu::MemoryUse::host);
    vertex_capacity_ = uint32_t(vertices);
    triangle_capacity_ = uint32_t(triangles);
}

void SurfaceMesher::record(VkCommandBuffer cmd, const gpu::Buffer& positions, uint32_t count, gpu::GpuTimer* timer) {
    positions_ = &positions;
    count_ = count;
    // The sampler is shared (a volume export samples it alone and grows it as the fluid spreads):
    // the offsets and their prefix sums follow its capacity as it is now, not as it was.
    reserve_lattice(sampler_.capacity());
    sampler_.record(cmd, positions, count, timer, vertex_capacity_, triangle_capacity_);
    {
        gpu::GpuScope scope(timer, cmd, "mesh_march");
        record_march(cmd);
    }
    sampler_.record_readback(cmd);
}

void SurfaceMesher::record_march(VkCommandBuffer cmd) {
    const gpu::Buffer* params = &sampler_.params_buffer();
    const gpu::Buffer* lattice = &sampler_.lattice_buffer();
    const gpu::Buffer* values = &sampler_.values();
    // Zero beyond the lattice too: the prefix sums run over the whole capacity.
    gpu::fill(*ctx_, cmd, *vertex_offset_, 0u);
    gpu::fill(*ctx_, cmd, *triangle_offset_, 0u);
    gpu::dispatch_indirect(*ctx_, cmd, classify_, *lattice,
                           {{"params", params},
                            {"lattice", lattice},
                            {"values", values},
                            {"table", table_},
                            {"vertex_count", vertex_offset_},
                            {"triangle_count", triangle_offset_}});
    const uint32_t entries = sampler_.capacity() + 1;
    scan_.record(cmd, *vertex_offset_, entries);
    scan_.record(cmd, *triangle_offset_, entries);
    // The totals into the lattice block (MeshLattice::totals), read back with it.
    const VkDeviceSize end = VkDeviceSize(entries - 1) * 4, totals = offsetof(shader::MeshLattice, totals);
    gpu::copy(*ctx_, cmd, *vertex_offset_, *lattice, {end, totals, 4});
    gpu::copy(*ctx_, cmd, *triangle_offset_, *lattice, {end, totals + 4, 4});
    gpu::dispatch_indirect(*ctx_, cmd, vertices_pass_, *lattice,
                           {{"params", params},
                            {"lattice", lattice},
                            {"values", values},
                            {"vertex_offset", vertex_offset_},
                            {"vertices", vertices_},
                            {"normals", normals_}});
    gpu::dispatch_indirect(*ctx_, cmd, triangles_pass_, *lattice,
                           {{"params", params},
                            {"lattice", lattice},
                            {"values", values},
                            {"table", table_},
                            {"vertex_offset", vertex_offset_},
                            {"triangle_offset", triangle_offset_},
                            {"triangles", triangles_}});
}

SurfaceMesh SurfaceMesher::collect(gpu::GpuTimer* timer) {
    shader::MeshLattice lattice = sampler_.lattice();
    // Twice more at most: once for the lattice, once for the output it then counts.
    for (int attempt = 0;; ++attempt) {
        const bool lattice_fits = lattice.dims.w <= sampler_.capacity();
        const bool output_fits = lattice.totals.x <= vertex_capacity_ && lattice.totals.y <= triangle_capacity_;
        if (lattice_fits && output_fits) break;
        if (attempt == 2 || !positions_)
            throw internal_failure("surface mesh: the mesh did not fit the buffers made for it");
        if (!lattice_fits)
            reserve_lattice(grown(lattice.dims.w, sampler_.sample_limit()));
        else
            reserve_output(grown(lattice.totals.x, UINT32_MAX), grown(lattice.totals.y, UINT32_MAX));
        gpu::submit_timed(*ctx_, timer, [&](VkCommandBuffer cmd) { record(cmd, *positions_, count_, timer); });
        lattice = sampler_.lattice();
    }
    SurfaceMesh mesh;
    mesh.origin = glm::vec3(lattice.origin_voxel);
    mesh.voxel = lattice.origin_voxel.w;
    mesh.dims = glm::uvec3(lattice.dims);
    mesh.vertices.resize(lattice.totals.x);
    mesh.normals.resize(lattice.totals.x);
    mesh.triangles.resize(lattice.totals.y);
    static_assert(sizeof(glm::vec3) == 12 && sizeof(glm::uvec3) == 12);
    std::memcpy(mesh.vertices.data(), vertices_->mapped, mesh.vertices.size() * 12);
    std::memcpy(mesh.normals.data(), normals_->mapped, mesh.normals.size() * 12);
    std::memcpy(mesh.triangles.data(), triangles_->mapped, mesh.triangles.size() * 12);
    return mesh;
}

SurfaceMesh SurfaceMesher::extract(const gpu::Buffer& positions, uint32_t count) {
    ctx_->submit_and_wait([&](VkCommandBuffer cmd) { record(cmd, positions, count, nullptr); });
    return collect();
}

std::vector<gpu::BufferReport> SurfaceMesher::memory_report() const {
    auto report = sampler_.memory_report();
    const gpu::BufferSet* sets[] = {&buffers_, lattice_buffers_.get(), output_buffers_.get()};
    for (const gpu::BufferSet* set : sets)
        if (set)
            for (auto& entry : set->report()) report.push_back(entry);
    return report;
}

}  // namespace aquaform
