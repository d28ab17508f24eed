// Surface meshes (render/density_sampler.h, render/surface_mesher.h, exports/mesh_export.h): the
// sampled field equals the renderer's field computed on the host, the GPU mesh equals the CPU
// marching cubes of the same volume, meshes of closed fluid are closed 2-manifolds of the right
// topology, the mesh lies on the surface the exhaustive ray-marched reference draws, the files
// read back, and `run --mesh-every` writes them.
#include <gtest/gtest.h>

#include "surface_field.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>

#include "core/error.h"
#include "exports/mesh_export.h"
#include "geometry/mesh.h"
#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "grid/neighbor_grid.h"
#include "render/density_sampler.h"
#include "render/marching_cubes.h"
#include "render/surface_mesher.h"
#include "render/surface_renderer.h"
#include "shaders/shared/render/render_kernels.h"
#include "sim/scene.h"
#include "tests/cli_helpers.h"
#include "tests/export_readers.h"
#include "tests/gpu_test.h"
#include "tests/particle_cube.h"

namespace aquaform {
namespace {

namespace fs = std::filesystem;
using namespace test_exports;
using testing::DeviceParticles;

class SurfaceMeshTest : public testing::GpuTest {};

constexpr float kSpacing = 0.02f;
constexpr float kParticleRadius = 0.5f * kSpacing;

/// A cube of 5^3 particles, two lone droplets and a pair, in a 0.24 m box: four separate bodies,
/// each a ball topologically. Positions are off the lattice, so no sample sits exactly on iso.
std::vector<glm::vec4> blob_and_droplets() {
    std::vector<glm::vec4> p = testing::particle_cube({0.062f, 0.071f, 0.066f}, kSpacing, 5);
    for (glm::vec3 x : {glm::vec3(0.2013f, 0.1917f, 0.1862f), glm::vec3(0.1931f, 0.0433f, 0.1987f),
                        glm::vec3(0.0437f, 0.1969f, 0.0512f), glm::vec3(0.0437f, 0.1969f, 0.0712f)})
        p.emplace_back(x, float(p.size()));
    return p;
}
constexpr size_t kBodies = 4;

/// Those particles on the device, in their scene.
struct TestFluid {
    Scene scene = testing::scene_with({{0.0f, 0.0f, 0.0f}, {0.24f, 0.24f, 0.24f}}, kSpacing);
    std::vector<glm::vec4> particles = blob_and_droplets();
    DeviceParticles device;
    explicit TestFluid(gpu::Context& ctx) : device(ctx, particles) {}
    ParticleDomain domain() const { return scene.particle_domain(); }
    /// The mesh at `voxel_radii`.
    SurfaceMesh mesh(gpu::Context& ctx, float voxel_radii = kDefaultMeshVoxelRadii) {
        SurfaceMesher mesher(ctx, domain(), device.count, SurfaceSettings{}, voxel_radii);
        return mesher.extract(device.buffer, device.count);
    }
};

/// phi(x) = V sum_j W(x - x_j, r) over every particle, on the host.
float cpu_phi(const DensitySampler& s, const std::vector<glm::vec4>& particles, glm::vec3 x) {
    const float r = s.radius();
    const float coeff = shader::cubic_coefficient(r);
    float sum = 0.0f;
    for (const glm::vec4& q : particles) {
        const glm::vec3 d = x - glm::vec3(q);
        sum += shader::cubic_kernel(glm::dot(d, d), 1.0f / r, coeff);
    }
    return kSpacing * kSpacing * kSpacing * sum;
}

/// The sampler's field at `p` from the unclipped `phi`: clipped at the walls of `domain`.
float clipped(float phi, glm::vec3 p, const Box& domain, const DensityVolume& v) {
    return shader::mesh_clip_to_walls(phi, p, domain.min, domain.max, v.iso, v.voxel);
}

/// Largest difference between the volume and the host's phi at every sample.
float max_field_error(const DensitySampler& s, const std::vector<glm::vec4>& particles, const DensityVolume& v,
                      const Box& domain) {
    float worst = 0.0f;
    for (uint32_t k = 0; k < v.dims.z; ++k)
        for (uint32_t j = 0; j < v.dims.y; ++j)
            for (uint32_t i = 0; i < v.dims.x; ++i) {
                const glm::vec3 p = v.position(i, j, k);
                worst = std::max(worst, std::abs(v.at(i, j, k) - clipped(cpu_phi(s, particles, p), p, domain, v)));
            }
    return worst;
}

TEST_F(SurfaceMeshTest, SampledVolumeEqualsTheRenderersFieldOnTheHost) {
    TestFluid fluid(ctx());
    const Scene& scene = fluid.scene;
    const auto& particles = fluid.particles;
    const DeviceParticles& device = fluid.device;
    SurfaceSettings isotropic;
    isotropic.surface = SurfaceKernel::isotropic;
    DensitySampler sampler(ctx(), fluid.domain(), device.count, isotropic);
    const DensityVolume volume = sampler.sample_volume(device.buffer, device.count);

    // The renderer's iso value for the same settings.
    const GridGeometry grid = render_grid(SurfaceSettings{}, scene.particle_domain()).value();
    const auto params = make_surface_params(SurfaceSettings{}, scene.particle_domain(), grid,
                                            camera_for_domain(scene.domain, 1.0f), 64, 64, device.count);
    EXPECT_FLOAT_EQ(volume.iso, params.iso);
    EXPECT_FLOAT_EQ(sampler.radius(), params.radius);
    EXPECT_FLOAT_EQ(volume.voxel, kDefaultMeshVoxelRadii * kParticleRadius);

    // The lattice covers the particles padded by r + a voxel, and its border is below iso.
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (const auto& p : particles) {
        lo = glm::min(lo, glm::vec3(p));
        hi = glm::max(hi, glm::vec3(p));
    }
    const glm::vec3 last = volume.position(volume.dims.x - 1, volume.dims.y - 1, volume.dims.z - 1);
    const float pad = sampler.radius() + volume.voxel;
    for (int a = 0; a < 3; ++a) {
        EXPECT_LE(volume.origin[a], lo[a] - pad + 1e-6f);
        EXPECT_GT(volume.origin[a], lo[a] - pad - volume.voxel);
        EXPECT_GE(last[a], hi[a] + pad - 1e-6f);
        EXPECT_LT(last[a], hi[a] + pad + volume.voxel);
    }
    ASSERT_EQ(volume.values.size(), volume.sample_count());
    // The sampler's anisotropic surface is the renderer's: the same kernels, the same field.
    {
        SurfaceSettings anisotropic;
        anisotropic.surface = SurfaceKernel::anisotropic;
        DensitySampler aniso_sampler(ctx(), fluid.domain(), device.count, anisotropic);
        const DensityVolume aniso = aniso_sampler.sample_volume(device.buffer, device.count);
        SurfaceRenderer renderer(ctx(), fluid.domain(), 32, 32, device.count);
        renderer.render({device.buffer, device.count}, camera_for_domain(scene.domain, 1.0f), anisotropic);
        const testing::FieldKernels kernels = testing::field_kernels(renderer, particles);
        ASSERT_EQ(kernels.centres.size(), particles.size());
        float aniso_worst = 0.0f;
        for (uint32_t k = 0; k < aniso.dims.z; ++k)
            for (uint32_t j = 0; j < aniso.dims.y; ++j)
                for (uint32_t i = 0; i < aniso.dims.x; ++i)
                    aniso_worst = std::max(
                        aniso_worst,
                        std::abs(aniso.at(i, j, k) -
                                 clipped(testing::cpu_field(renderer.params(), kernels, aniso.position(i, j, k)),
                                         aniso.position(i, j, k), scene.domain, aniso)));
        EXPECT_LT(aniso_worst, 1e-4f) << "the anisotropic volume differs from the renderer's field";
        EXPECT_FLOAT_EQ(aniso.iso, volume.iso);
    }
    const float worst = max_field_error(sampler, particles, volume, scene.domain);
    std::printf("[ field ] %ux%ux%u samples, max |phi_gpu - phi_cpu| = %.2e (iso %.3f)\n", volume.dims.x, volume.dims.y,
                volume.dims.z, worst, volume.iso);
    EXPECT_LT(worst, 2e-5f);
    EXPECT_GT(*std::max_element(volume.values.begin(), volume.values.end()), 0.9f);  // inside the cube

    // The same volume read in place from a grid the positions are sorted by (the run's frame grid).
    gpu::BufferSet buffers(ctx());
    NeighborGrid frame_grid(ctx(), buffers, grid, device.count, "test.grid");
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { frame_grid.build(cmd, device.buffer, device.count, nullptr); });
    const auto order = gpu::download_vector<uint32_t>(ctx(), frame_grid.order(), device.count);
    std::vector<glm::vec4> sorted;
    for (uint32_t j : order) sorted.push_back(particles[j]);
    DeviceParticles sorted_device(ctx(), sorted);
    sampler.share_grid(&frame_grid);
    ASSERT_TRUE(sampler.reads_in_place());
    const DensityVolume in_place = sampler.sample_volume(sorted_device.buffer, sorted_device.count);
    ASSERT_EQ(in_place.dims, volume.dims);
    EXPECT_LT(max_field_error(sampler, particles, in_place, fluid.scene.domain), 2e-5f);
}

// Every sample sums the field: over the device's work budget the sample pass runs as several
// dispatches, each a share of the samples, and the volume is the same to the bit.
TEST_F(SurfaceMeshTest, ASamplePassOverTheWorkBudgetIsSplitAndGivesTheSameVolume) {
    TestFluid fluid(ctx());
    DensitySampler sampler(ctx(), fluid.domain(), fluid.device.count, SurfaceSettings{});
    const DensityVolume whole = sampler.sample_volume(fluid.device.buffer, fluid.device.count);
    ASSERT_EQ(sampler.sample_slices(), 1u);
    const uint64_t saved = ctx().info().dispatch_work_budget;
    ctx().override_dispatch_work_budget(uint64_t(double(sampler.capacity()) * 216.0 / 7.0) + 1);
    // A sampler of its own: no value left over from the whole pass can hide a missed sample.
    DensitySampler split_sampler(ctx(), fluid.domain(), fluid.device.count, SurfaceSettings{});
    const DensityVolume split = split_sampler.sample_volume(fluid.device.buffer, fluid.device.count);
    const uint32_t slices = split_sampler.sample_slices();
    ctx().override_dispatch_work_budget(saved);
    ASSERT_EQ(split_sampler.capacity(), sampler.capacity()) << "both grew to the same lattice";
    EXPECT_EQ(slices, 7u);
    ASSERT_EQ(split.values.size(), whole.values.size());
    size_t differ = 0, inside = 0;
    for (size_t i = 0; i < whole.values.size(); ++i) {
        differ += whole.values[i] != split.values[i];
        inside += whole.values[i] > whole.iso;
    }
    EXPECT_GT(inside, 100u);
    EXPECT_EQ(differ, 0u) << "samples the split pass missed or summed differently";
}

TEST_F(SurfaceMeshTest, GpuMeshEqualsTheCpuMarchingCubesIndexForIndex) {
    TestFluid fluid(ctx());
    const DeviceParticles& device = fluid.device;
    SurfaceMesher mesher(ctx(), fluid.domain(), device.count);
    // The first guess of the buffers (a compact cube of the particles) is too small for the
    // droplets' spread: collect() must grow them and extract again.
    const uint32_t first_capacity = mesher.sampler().capacity();
    const SurfaceMesh gpu_mesh = mesher.extract(device.buffer, device.count);
    EXPECT_GT(uint64_t(gpu_mesh.dims.x) * gpu_mesh.dims.y * gpu_mesh.dims.z, first_capacity);

    const SurfaceMesh cpu_mesh = marching_cubes(mesher.sampler().sample_volume(device.buffer, device.count));
    ASSERT_GT(cpu_mesh.triangles.size(), 1000u);
    ASSERT_EQ(gpu_mesh.vertices.size(), cpu_mesh.vertices.size());
    ASSERT_EQ(gpu_mesh.triangles.size(), cpu_mesh.triangles.size());
    EXPECT_EQ(gpu_mesh.dims, cpu_mesh.dims);
    EXPECT_TRUE(gpu_mesh.triangles == cpu_mesh.triangles);
    float position_error = 0.0f, normal_error = 0.0f;
    for (size_t i = 0; i < cpu_mesh.vertices.size(); ++i) {
        position_error = std::max(position_error, glm::length(gpu_mesh.vertices[i] - cpu_mesh.vertices[i]));
        normal_error = std::max(normal_error, glm::length(gpu_mesh.normals[i] - cpu_mesh.normals[i]));
    }
    std::printf("[ mesh ] %zu vertices, %zu triangles; GPU vs CPU: positions within %.2e m, normals within %.2e\n",
                cpu_mesh.vertices.size(), cpu_mesh.triangles.size(), position_error, normal_error);
    EXPECT_LT(position_error, 1e-6f);
    EXPECT_LT(normal_error, 1e-4f);
}

TEST_F(SurfaceMeshTest, ALatticeBeyondTheDeviceIsRefusedWithTheFiguresAndTheFix) {
    // Two particles at opposite corners of a 4 m tank: half a billion samples at a quarter spacing.
    const Scene scene = testing::scene_with({{0.0f, 0.0f, 0.0f}, {4.0f, 4.0f, 4.0f}}, kSpacing);
    DeviceParticles device(ctx(), {glm::vec4(0.01f, 0.01f, 0.01f, 0.0f), glm::vec4(3.99f, 3.99f, 3.99f, 1.0f)});
    SurfaceMesher mesher(ctx(), scene.particle_domain(), device.count);
    try {
        mesher.extract(device.buffer, device.count);
        FAIL() << "expected a Failure";
    } catch (const Failure& e) {
        const std::string text = e.what();
        EXPECT_EQ(e.kind(), Failure::Kind::resource) << text;
        EXPECT_NE(text.find("samples"), std::string::npos) << text;
        EXPECT_NE(text.find("--particles"), std::string::npos) << text;
        EXPECT_EQ(text.find('\n'), std::string::npos) << text;
    }
}

/// The topology of a mesh: edges with other than two triangles (or two running the same way),
/// non-finite vertices, and per connected part its Euler characteristic and signed volume.
struct Topology {
    size_t open_or_non_manifold_edges = 0;
    size_t misoriented_edges = 0;
    size_t non_finite_vertices = 0;
    std::vector<long> euler;     // per part
    std::vector<double> volume;  // per part, > 0: faces point out
};

Topology topology(const SurfaceMesh& mesh) {
    Topology t;
    for (const glm::vec3& v : mesh.vertices) t.non_finite_vertices += !std::isfinite(v.x + v.y + v.z);
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const glm::uvec3& f : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
    std::map<std::pair<uint32_t, uint32_t>, int> undirected;
    for (const auto& [e, n] : directed) {
        undirected[{std::min(e.first, e.second), std::max(e.first, e.second)}] += n;
        const auto back = directed.find({e.second, e.first});
        t.misoriented_edges += n != 1 || back == directed.end() || back->second != 1;
    }
    for (const auto& [e, n] : undirected) t.open_or_non_manifold_edges += n != 2;
    // Parts: union-find over the triangles' vertices.
    std::vector<uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const glm::uvec3& f : mesh.triangles) {
        parent[find(f.y)] = find(f.x);
        parent[find(f.z)] = find(f.x);
    }
    std::map<uint32_t, size_t> part_of;
    for (uint32_t v = 0; v < parent.size(); ++v)
        if (!part_of.count(find(v))) part_of[find(v)] = part_of.size();
    t.euler.assign(part_of.size(), 0);
    t.volume.assign(part_of.size(), 0.0);
    for (uint32_t v = 0; v < parent.size(); ++v) ++t.euler[part_of[find(v)]];
    for (const auto& [e, n] : undirected) --t.euler[part_of[find(e.first)]];
    for (const glm::uvec3& f : mesh.triangles) {
        const size_t part = part_of[find(f.x)];
        ++t.euler[part];
        const glm::dvec3 a(mesh.vertices[f.x]), b(mesh.vertices[f.y]), c(mesh.vertices[f.z]);
        t.volume[part] += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return t;
}

TEST_F(SurfaceMeshTest, ClosedFluidGivesClosedOutwardBallsOnePerBody) {
    TestFluid fluid(ctx());
    const Topology t = topology(fluid.mesh(ctx()));
    std::printf("[ topology ] %zu parts, Euler characteristics", t.euler.size());
    for (long e : t.euler) std::printf(" %ld", e);
    std::printf("; %zu open or non-manifold edges\n", t.open_or_non_manifold_edges);
    EXPECT_EQ(t.non_finite_vertices, 0u);
    EXPECT_EQ(t.open_or_non_manifold_edges, 0u);
    EXPECT_EQ(t.misoriented_edges, 0u);
    ASSERT_EQ(t.euler.size(), kBodies);
    for (size_t part = 0; part < kBodies; ++part) {
        EXPECT_EQ(t.euler[part], 2) << "part " << part << " is not a sphere topologically";
        EXPECT_GT(t.volume[part], 0.0) << "part " << part << " faces inward";
    }
    // The cube's volume: about its particles' (125 spacings^3), within the lone-radius rim.
    const double cube = *std::max_element(t.volume.begin(), t.volume.end());
    EXPECT_NEAR(cube, 125.0 * kSpacing * kSpacing * kSpacing, 0.35 * 125.0 * kSpacing * kSpacing * kSpacing);
}

// The table on fields no fluid makes: random samples (every one of the 256 cases, ambiguous
// faces everywhere) inside a border below iso. A fan over each loop instead of the search in
// triangulate() would join vertices across ambiguous faces and fail here.
TEST(MarchingCubesTable, RandomFieldsGiveClosedConsistentlyOrientedSurfaces) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<bool> seen(256, false);
    for (int trial = 0; trial < 8; ++trial) {
        DensityVolume v;
        v.dims = {11, 12, 13};
        v.voxel = 0.1f;
        v.iso = 0.5f;
        v.values.resize(v.sample_count());
        for (uint32_t k = 0; k < v.dims.z; ++k)
            for (uint32_t j = 0; j < v.dims.y; ++j)
                for (uint32_t i = 0; i < v.dims.x; ++i) {
                    const bool border =
                        i == 0 || j == 0 || k == 0 || i + 1 == v.dims.x || j + 1 == v.dims.y || k + 1 == v.dims.z;
                    v.values[v.index(i, j, k)] = border ? 0.0f : uniform(rng);
                }
        for (uint32_t k = 0; k + 1 < v.dims.z; ++k)
            for (uint32_t j = 0; j + 1 < v.dims.y; ++j)
                for (uint32_t i = 0; i + 1 < v.dims.x; ++i) {
                    uint32_t pattern = 0;
                    for (uint32_t c = 0; c < 8; ++c) {
                        const glm::uvec3 p = glm::uvec3(i, j, k) + shader::mesh_corner(c);
                        pattern |= uint32_t(v.at(p.x, p.y, p.z) >= v.iso) << c;
                    }
                    seen[pattern] = true;
                }
        const Topology t = topology(marching_cubes(v));
        EXPECT_EQ(t.open_or_non_manifold_edges, 0u) << "trial " << trial;
        EXPECT_EQ(t.misoriented_edges, 0u) << "trial " << trial;
        for (double volume : t.volume) EXPECT_GT(volume, 0.0) << "trial " << trial;
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), true), 256);
}

/// Distance from p to triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
float point_triangle_distance(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return glm::length(p - a);
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return glm::length(p - b);
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return glm::length(p - c);
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const float denom = 1.0f / (va + vb + vc);
    return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

/// Distance from p to the nearest triangle of the mesh (every triangle: the meshes are small).
float distance_to_mesh(const SurfaceMesh& mesh, glm::vec3 p) {
    float best = INFINITY;
    for (const glm::uvec3& f : mesh.triangles) {
        const glm::vec3 a = mesh.vertices[f.x], b = mesh.vertices[f.y], c = mesh.vertices[f.z];
        // A triangle is within a voxel of its vertices: skip those farther than the best so far.
        if (glm::length(p - a) - 2.0f * mesh.voxel > best) continue;
        best = std::min(best, point_triangle_distance(p, a, b, c));
    }
    return best;
}

TEST_F(SurfaceMeshTest, MeshLiesOnTheExhaustiveReferenceSurface) {
    TestFluid fluid(ctx());
    SurfaceRenderer renderer(ctx(), fluid.domain(), 128, 128, fluid.device.count);
    SurfaceSettings reference;
    reference.method = SurfaceMethod::reference;
    const SurfaceFrame frame = renderer.render({fluid.device.buffer, fluid.device.count},
                                               camera_for_domain(fluid.scene.domain, 1.0f), reference);
    ASSERT_EQ(renderer.cut_rays(), 0u);
    // Against the default lattice, and one twice as coarse for the figures in density_sampler.h.
    for (float voxel_radii : {kDefaultMeshVoxelRadii, 2.0f * kDefaultMeshVoxelRadii}) {
        const SurfaceMesh mesh = fluid.mesh(ctx(), voxel_radii);
        double sum = 0.0;
        float worst = 0.0f;
        size_t hits = 0;
        for (size_t i = 0; i < frame.hit.size(); ++i) {
            if (!frame.has_surface(i)) continue;
            const float d = distance_to_mesh(mesh, glm::vec3(frame.hit[i])) / kParticleRadius;
            sum += d;
            worst = std::max(worst, d);
            ++hits;
        }
        ASSERT_GT(hits, 1000u);
        const double mean = sum / double(hits);
        std::printf(
            "[ accuracy ] voxel %.2f particle radii: %zu triangles; over %zu reference pixels the mesh lies "
            "%.4f particle radii from the surface on average, %.3f at most\n",
            voxel_radii, mesh.triangles.size(), hits, mean, worst);
        if (voxel_radii == kDefaultMeshVoxelRadii) {
            EXPECT_LT(mean, 0.05);
            EXPECT_LT(worst, 0.5f);
        }
    }
}

TEST_F(SurfaceMeshTest, WrittenFilesReadBackWithTheProjectsObjLoaderAndAsPly) {
    TestFluid fluid(ctx());
    const SurfaceMesh mesh = fluid.mesh(ctx());
    const fs::path dir = test_cli::temp_dir("surface_mesh_files");

    ASSERT_TRUE(write_mesh(dir / "surface.obj", mesh, MeshFormat::obj));
    auto loaded = geometry::load_obj(dir / "surface.obj");
    ASSERT_TRUE(loaded) << loaded.error();
    EXPECT_EQ(loaded.value().mesh.vertices.size(), mesh.vertices.size());
    ASSERT_EQ(loaded.value().mesh.faces.size(), mesh.triangles.size());
    EXPECT_TRUE(loaded.value().report.watertight()) << geometry::describe(loaded.value().report);
    EXPECT_EQ(loaded.value().report.reoriented_face_count, 0u);
    EXPECT_GT(loaded.value().report.signed_volume, 0.0);
    for (size_t i = 0; i < mesh.vertices.size(); ++i) ASSERT_EQ(loaded.value().mesh.vertices[i], mesh.vertices[i]);
    EXPECT_TRUE(loaded.value().mesh.faces == mesh.triangles);

    ASSERT_TRUE(write_mesh(dir / "surface.ply", mesh, MeshFormat::ply));
    const SurfaceMesh ply = read_mesh_ply(dir / "surface.ply");
    EXPECT_TRUE(ply.vertices == mesh.vertices);
    EXPECT_TRUE(ply.normals == mesh.normals);
    EXPECT_TRUE(ply.triangles == mesh.triangles);

    // A file that cannot be written is an error naming it.
    auto refused = write_mesh(dir / "no_such_dir" / "surface.obj", mesh, MeshFormat::obj);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().find("no_such_dir"), std::string::npos) << refused.error();
    EXPECT_FALSE(parse_mesh_format("stl"));
    fs::remove_all(dir);
}

TEST(SurfaceMeshRun, MeshEveryWritesAMeshPerFrameAndRefusesUnknownFormats) {
    const fs::path dir = test_cli::temp_dir("surface_mesh_run");
    const std::string scene = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    auto o = test_cli::run_aquaform(
        "run " + scene + " --frames 2 --particles 300 --no-png --mesh-every 1 --out " + (dir / "obj").string(),
        "AQUAFORM_VALIDATION=1");
    ASSERT_EQ(o.exit_code, 0) << o.output;
    for (const char* name : {"surface_0000.obj", "surface_0001.obj"}) {
        auto loaded = geometry::load_obj(dir / "obj" / name);
        ASSERT_TRUE(loaded) << name << ": " << loaded.error();
        EXPECT_GT(loaded.value().mesh.faces.size(), 500u) << name;
        EXPECT_TRUE(loaded.value().report.watertight()) << name << ": " << geometry::describe(loaded.value().report);
    }
    EXPECT_FALSE(fs::exists(dir / "obj" / "surface_0002.obj"));

    o = test_cli::run_aquaform("run " + scene +
                               " --frames 3 --particles 300 --no-png --mesh-every 2 --mesh-format ply "
                               "--out " +
                               (dir / "ply").string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    EXPECT_GT(read_mesh_ply(dir / "ply" / "surface_0000.ply").triangles.size(), 500u);
    // Frames 0 and 2: the meshes are numbered by their own count, exports.csv gives the frame.
    EXPECT_TRUE(fs::exists(dir / "ply" / "surface_0001.ply"));
    EXPECT_FALSE(fs::exists(dir / "ply" / "surface_0002.ply"));
    EXPECT_NE(test_cli::read_file(dir / "ply" / "exports.csv").find("surface_0001.ply,mesh,2,"), std::string::npos);

    o = test_cli::run_aquaform("run " + scene + " --frames 1 --mesh-every 1 --mesh-format xyz --out " +
                               (dir / "xyz").string());
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
    EXPECT_NE(o.output.find("--mesh-format"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("obj"), std::string::npos) << o.output;
    fs::remove_all(dir);
}

TEST(SurfaceMeshRun, TheExportedSurfaceStaysInsideTheTank) {
    // A dam break pressed against its walls and floor: the kernels of the particles there reach
    // about r beyond them, and an unclipped surface pokes about 2 cm through the glass.
    const fs::path dir = test_cli::temp_dir("surface_in_tank");
    const std::string scene_path = std::string(AQUAFORM_ASSETS_DIR) + "/scenes/dam_break.json";
    auto o = test_cli::run_aquaform("run " + scene_path +
                                    " --frames 31 --particles 3000 --no-png --mesh-every 10 "
                                    "--vdb-every 10 --out " +
                                    dir.string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
    auto scene = load_scene(scene_path);
    ASSERT_TRUE(scene) << scene.error();
    const Box tank = scene.value().domain;
    size_t meshes = 0, volumes = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("surface_", 0) == 0) {
            ++meshes;
            auto loaded = geometry::load_obj(entry.path());
            ASSERT_TRUE(loaded) << name << ": " << loaded.error();
            glm::vec3 lo(1e9f), hi(-1e9f);
            for (const glm::vec3& v : loaded.value().mesh.vertices) lo = glm::min(lo, v), hi = glm::max(hi, v);
            for (int a = 0; a < 3; ++a) {
                EXPECT_GE(lo[a], tank.min[a] - 1e-5f) << name << ": the surface pokes through the wall on axis " << a;
                EXPECT_LE(hi[a], tank.max[a] + 1e-5f) << name << ": the surface pokes through the wall on axis " << a;
            }
            // It reaches the wall it leans on (the column stands on the floor at the left wall).
            EXPECT_LT(lo.x, tank.min.x + 0.005f) << name;
            EXPECT_LT(lo.y, tank.min.y + 0.005f) << name;
        }
        if (name.rfind("density_", 0) == 0) {
            ++volumes;
            openvdb::initialize();
            openvdb::io::File file(entry.path().string());
            file.open();
            auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("density"));
            file.close();
            ASSERT_TRUE(grid) << name;
            const float iso = grid->metaValue<float>("aquaform_iso");
            // Where a voxel is inside the fluid (above the iso level), its centre is in the tank.
            for (auto on = grid->cbeginValueOn(); on; ++on) {
                if (*on <= iso) continue;
                const openvdb::Vec3d p = grid->indexToWorld(on.getCoord());
                for (int a = 0; a < 3; ++a)
                    ASSERT_TRUE(p[a] >= tank.min[a] - 1e-5 && p[a] <= tank.max[a] + 1e-5)
                        << name << ": fluid at " << p << " outside the tank";
            }
        }
    }
    EXPECT_EQ(meshes, 4u);
    EXPECT_EQ(volumes, 4u);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace aquaform
