// Whitewater (sim/whitewater.h, shaders/shared/whitewater_layout.h): the GPU's potentials match a
// CPU computation of Ihmsen et al.'s formulas on the same particles; the pool never holds more
// than its capacity and counts what did not fit; no whitewater particle leaves the tank or enters a
// solid; the fluid does not feel its whitewater; the scene's section is checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/json_fields.h"
#include "geometry/animation.h"
#include "geometry/inside.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "gpu/staging.h"
#include "render/registry.h"
#include "render/solids_view.h"
#include "render/whitewater_layer.h"
#include "shaders/shared/core/sph_kernels.h"
#include "sim/pbf_solver.h"
#include "sim/whitewater.h"
#include "tests/cli_helpers.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

class WhitewaterTest : public testing::GpuTest {};

/// Two blocks thrown at each other in a 0.4 m tank (spacing 0.02 m): they trap air where they
/// meet and throw crests up.
Scene collision(const std::string& whitewater_json = "{}") {
    Scene scene = testing::scene_with({glm::vec3(0.0f), glm::vec3(0.4f, 0.3f, 0.2f)}, 0.02f);
    scene.fluid_blocks = {{glm::vec3(0.0f), glm::vec3(0.12f, 0.12f, 0.2f)},
                          {glm::vec3(0.28f, 0.0f, 0.0f), glm::vec3(0.4f, 0.12f, 0.2f)}};
    scene.block_fills = {BlockFill{std::nullopt, glm::vec3(2.0f, 0.0f, 0.0f)},
                         BlockFill{std::nullopt, glm::vec3(-2.0f, 0.0f, 0.0f)}};
    scene.whitewater = read_whitewater(nlohmann::json::parse(whitewater_json));
    return scene;
}

/// Ihmsen et al.'s potentials on the CPU (shaders/shared/whitewater_layout.h), by brute force.
std::vector<glm::vec3> cpu_potentials(const ParticleSnapshot& s, const shader::SimParams& p) {
    const size_t n = s.x.size();
    std::vector<glm::vec3> normals(n, glm::vec3(0.0f));
    for (size_t i = 0; i < n; ++i) {
        glm::vec3 gradient(0.0f);
        for (size_t j = 0; j < n; ++j) {
            const glm::vec3 r = glm::vec3(s.x[i]) - glm::vec3(s.x[j]);
            const float r2 = glm::dot(r, r);
            if (j != i && r2 < p.h2) gradient += shader::spiky_gradient(r, r2, p.h, p.spiky_coeff);
        }
        const glm::vec3 normal = -p.volume * gradient;
        normals[i] = glm::length(normal) * p.h > 0.1f ? glm::normalize(normal) : glm::vec3(0.0f);
    }
    std::vector<glm::vec3> out(n);
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3 vi(s.v[i]), ni = normals[i];
        float trapped = 0.0f, curvature = 0.0f;
        for (size_t j = 0; j < n; ++j) {
            const glm::vec3 r = glm::vec3(s.x[i]) - glm::vec3(s.x[j]);
            const float r2 = glm::dot(r, r);
            if (j == i || r2 >= p.h2 || r2 <= 0.0f) continue;
            const float d = std::sqrt(r2), w = 1.0f - d / p.h;
            const glm::vec3 vij = vi - glm::vec3(s.v[j]);
            const float speed = glm::length(vij);
            if (speed > 0.0f) trapped += speed * (1.0f - glm::dot(vij / speed, r / d)) * w;
            const glm::vec3 nj = normals[j];
            if (glm::dot(ni, ni) > 0.0f && glm::dot(nj, nj) > 0.0f && glm::dot(-r / d, ni) < 0.0f)
                curvature += (1.0f - glm::dot(ni, nj)) * w;
        }
        const float speed = glm::length(vi);
        const float crest = speed > 0.0f && glm::dot(vi / speed, ni) >= 0.6f ? curvature : 0.0f;
        out[i] = {trapped, crest, 0.5f * speed * speed};
    }
    return out;
}

/// Runs `frames` of `scene`, then a whitewater of the test's own, sized for the solver's capacity,
/// one step on the solver's state as the frame left it (for its count); returns each potential's
/// largest CPU value and checks the GPU's against the CPU's on the same particles.
glm::dvec3 expect_potentials_of_the_cpu(gpu::Context& ctx, const Scene& scene, int frames) {
    PbfSolver solver(ctx, scene);
    solver.set_frame_grid(true);  // frames end with lists of the final positions: the CPU's pairs
    for (int f = 0; f < frames; ++f) solver.run_frame(nullptr);
    Whitewater ww(ctx, scene, solver.capacity(), false);
    ctx.submit_and_wait([&](VkCommandBuffer cmd) {
        ww.record_step(cmd, solver.params_buffer(), solver.positions(), solver.velocities(), solver.grid(),
                       solver.boundary_nodes(), solver.particle_count());
    });
    const std::vector<glm::vec4> gpu = ww.potentials();
    const std::vector<glm::vec3> cpu = cpu_potentials(solver.snapshot(), solver.params());
    EXPECT_EQ(cpu.size(), solver.particle_count());
    EXPECT_GE(gpu.size(), cpu.size());
    glm::dvec3 largest(0.0), worst(0.0);
    for (size_t i = 0; i < std::min(cpu.size(), gpu.size()); ++i)
        for (int k = 0; k < 3; ++k) {
            largest[k] = std::max(largest[k], double(cpu[i][k]));
            worst[k] = std::max(worst[k], std::abs(double(gpu[i][k]) - double(cpu[i][k])));
        }
    for (int k = 0; k < 3; ++k) EXPECT_LT(worst[k], 1e-3 * largest[k] + 1e-5) << "potential " << k;
    return largest;
}

TEST_F(WhitewaterTest, ThePotentialsAreIhmsensOnTheSameParticles) {
    const glm::dvec3 largest = expect_potentials_of_the_cpu(ctx(), collision(), 4);
    // The collision makes every potential: trapped air where the blocks meet, crests on the sheet
    // they throw up, kinetic energy everywhere.
    EXPECT_GT(largest[0], 5.0) << "no trapped air where the blocks collide";
    EXPECT_GT(largest[1], 1.0) << "no wave crest";
    EXPECT_GT(largest[2], 1.0) << "no kinetic energy";
}

TEST_F(WhitewaterTest, WithWaterComingAndGoingThePotentialsAreOfTheWaterAlive) {
    // A jet at 2.5 m/s into a pool whose corner drains: after emission and removal the particles
    // alive are compacted, and the whitewater reads exactly them.
    auto scene = parse_scene(R"({"name": "jet", "domain": {"min": [0, 0, 0], "max": [0.4, 0.4, 0.2]},
        "particle_spacing": 0.02, "frames": 20, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.4, 0.06, 0.2]}],
        "emitters": {"jet": {"position": [0.1, 0.3, 0.1], "direction": [1, -1, 0], "radius": 0.03, "speed": 2.5}},
        "sinks": {"drain": {"box": {"min": [0.3, 0, 0], "max": [0.4, 0.04, 0.2]}}},
        "whitewater": {"k_trapped_air": 40000, "k_wave_crest": 400000}})",
                             "jet");
    ASSERT_TRUE(scene.ok()) << scene.error();
    PbfSolver solver(ctx(), scene.value());
    uint64_t emitted = 0;
    for (int f = 0; f < 20; ++f) {
        const FrameStats stats = solver.run_frame(nullptr);
        emitted += stats.whitewater->emitted;
        for (const glm::vec4& p : solver.whitewater()->snapshot().x)
            ASSERT_TRUE(glm::all(glm::greaterThanEqual(glm::vec3(p), scene.value().domain.min)) &&
                        glm::all(glm::lessThanEqual(glm::vec3(p), scene.value().domain.max)))
                << "frame " << f << ": whitewater outside the tank";
        if (f == 19) {
            EXPECT_GT(stats.flow->emitted, 0u);
            EXPECT_GT(stats.flow->removed, 0u) << "the drain took water";
        }
    }
    EXPECT_GT(emitted, 0u) << "the jet's landing made whitewater";
    const glm::dvec3 largest = expect_potentials_of_the_cpu(ctx(), scene.value(), 20);
    EXPECT_GT(largest[2], 1.0) << "the jet's kinetic energy";
}

TEST_F(WhitewaterTest, ThePoolNeverHoldsMoreThanItsCapacityAndCountsWhatDidNotFit) {
    const Scene scene = collision(R"({"capacity": 300, "k_trapped_air": 40000, "k_wave_crest": 400000})");
    PbfSolver solver(ctx(), scene);
    ASSERT_NE(solver.whitewater(), nullptr);
    EXPECT_EQ(solver.whitewater()->capacity(), 300u);
    uint64_t dropped = 0, emitted = 0;
    for (int f = 0; f < 12; ++f) {
        const FrameStats stats = solver.run_frame(nullptr);
        ASSERT_TRUE(stats.whitewater);
        const WhitewaterCounts c = *stats.whitewater;
        EXPECT_LE(c.live(), 300u) << "frame " << f;
        EXPECT_EQ(solver.whitewater()->snapshot().x.size(), c.live()) << "frame " << f;
        dropped += c.dropped;
        emitted += c.emitted;
    }
    EXPECT_GT(emitted, 600u) << "the collision must ask for more than the pool holds";
    EXPECT_GT(dropped, 0u) << "a full pool must count what it could not keep";
}

TEST_F(WhitewaterTest, NoWhitewaterParticleLeavesTheTankOrEntersASolid) {
    auto dir = test_cli::temp_dir("whitewater_solid");
    ASSERT_TRUE(geometry::write_obj(dir / "block.obj",
                                    geometry::make_box({glm::vec3(0.18f, 0.0f, 0.05f), glm::vec3(0.22f, 0.2f, 0.15f)}))
                    .ok());
    std::ofstream(dir / "scene.json")
        << R"({"name": "whitewater against a block", "domain": {"min": [0, 0, 0], "max": [0.4, 0.3, 0.2]},
        "particle_spacing": 0.02, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.12, 0.12, 0.2], "velocity": [2, 0, 0]},
        {"min": [0.28, 0, 0], "max": [0.4, 0.12, 0.2], "velocity": [-2, 0, 0]}],
        "obstacles": {"block": {"file": "block.obj"}}, "whitewater": {"k_trapped_air": 40000, "k_wave_crest": 400000}})";
    auto scene = load_scene(dir / "scene.json");
    ASSERT_TRUE(scene.ok()) << scene.error();
    const std::vector<glm::vec3> block = scene.value().obstacles[0].shape->mesh_at(0.0).triangle_soup();
    PbfSolver solver(ctx(), scene.value());
    size_t seen = 0;
    for (int f = 0; f < 20; ++f) {
        solver.run_frame(nullptr);
        const WhitewaterSnapshot d = solver.whitewater()->snapshot();
        seen = std::max(seen, d.x.size());
        for (const glm::vec4& p : d.x) {
            const glm::vec3 q(p);
            ASSERT_TRUE(glm::all(glm::greaterThanEqual(q, scene.value().domain.min)) &&
                        glm::all(glm::lessThanEqual(q, scene.value().domain.max)))
                << "frame " << f << ": a whitewater particle left the tank at " << q.x << " " << q.y << " " << q.z;
            ASSERT_FALSE(geometry::is_inside(block, q))
                << "frame " << f << ": a whitewater particle in the block at " << q.x << " " << q.y << " " << q.z;
            ASSERT_GT(p.w, 0.0f) << "a particle whose life ran out is still in the pool";
        }
    }
    EXPECT_GT(seen, 100u) << "the test needs whitewater";
}

TEST_F(WhitewaterTest, TheFluidDoesNotFeelItsWhitewater) {
    Scene with = collision(R"({"k_trapped_air": 40000})"), off = collision(R"({"enabled": false})");
    PbfSolver a(ctx(), with), b(ctx(), off);
    EXPECT_EQ(b.whitewater(), nullptr) << "enabled: false makes none";
    for (int f = 0; f < 6; ++f) {
        a.run_frame(nullptr);
        b.run_frame(nullptr);
    }
    ASSERT_GT(a.whitewater()->snapshot().x.size(), 0u);
    const ParticleSnapshot sa = a.snapshot(), sb = b.snapshot();
    ASSERT_EQ(sa.x.size(), sb.x.size());
    for (size_t i = 0; i < sa.x.size(); ++i) ASSERT_EQ(sa.x[i], sb.x[i]) << "particle " << i << ": bit for bit";
}

/// Whitewater particles placed by hand: a pool of one generation and its counters.
struct HandPool {
    gpu::BufferSet buffers;
    WhitewaterView view;
    HandPool(gpu::Context& ctx, const std::vector<glm::vec4>& x) : buffers(ctx) {
        gpu::Buffer& px = buffers.add("test.ww.x", x.size() * 16);
        gpu::Buffer& pv = buffers.add("test.ww.v", x.size() * 16);
        gpu::Buffer& counters = buffers.add("test.ww.counters", WW_COUNTERS * 4, gpu::MemoryUse::host);
        const std::vector<glm::vec4> v(x.size(), glm::vec4(0.0f, 0.0f, 0.0f, float(WHITEWATER_FOAM)));
        gpu::upload(ctx, px, x.data(), x.size() * 16);
        gpu::upload(ctx, pv, v.data(), v.size() * 16);
        auto* c = static_cast<uint32_t*>(counters.mapped);
        std::fill(c, c + WW_COUNTERS, 0u);
        c[WW_NEXT] = uint32_t(x.size());
        c[WW_GENERATION] = 0u;
        view = {{&px, &px}, {&pv, &pv}, &counters, uint32_t(x.size()), 0.01f};
    }
};

/// A cloud of foam in a small box, `n` particles.
std::vector<glm::vec4> cloud(const Box& box, int n) {
    std::vector<glm::vec4> out;
    for (int i = 0; i < n; ++i) {
        const glm::vec3 t(float(i % 7) / 6.0f, float((i / 7) % 7) / 6.0f, float(i / 49) / float(std::max(1, n / 49)));
        out.emplace_back(box.min + t * (box.max - box.min), 1.0f);
    }
    return out;
}

/// Pixels of `a` that differ from `b` by more than 4 in a channel over the columns [x0, x1).
size_t changed(const Image& a, const Image& b, uint32_t x0, uint32_t x1) {
    size_t n = 0;
    for (uint32_t y = 0; y < a.height; ++y)
        for (uint32_t x = x0; x < x1; ++x)
            for (int k = 0; k < 3; ++k)
                if (std::abs(int(a.rgba[(size_t(y) * a.width + x) * 4 + k]) -
                             int(b.rgba[(size_t(y) * b.width + x) * 4 + k])) > 4) {
                    ++n;
                    break;
                }
    return n;
}

/// How much whiter `a` is than `b` over the columns [x0, x1): the sum of the rise of each
/// pixel's darkest channel.
double whiter(const Image& a, const Image& b, uint32_t x0, uint32_t x1) {
    double sum = 0.0;
    for (uint32_t y = 0; y < a.height; ++y)
        for (uint32_t x = x0; x < x1; ++x) {
            const uint8_t* p = &a.rgba[(size_t(y) * a.width + x) * 4];
            const uint8_t* q = &b.rgba[(size_t(y) * b.width + x) * 4];
            sum += std::max(0, int(std::min({p[0], p[1], p[2]})) - int(std::min({q[0], q[1], q[2]})));
        }
    return sum;
}

TEST_F(WhitewaterTest, EveryMethodDrawsItWithDepthAgainstTheWaterAndWithoutItTheFrameIsItsOwn) {
    // A block of water on the right of the tank; foam in the air on the left, and on the right
    // once in front of the water and once 8 cm inside it (bubbles seen through the water).
    Scene scene = testing::scene_with({glm::vec3(0.0f), glm::vec3(0.6f, 0.3f, 0.4f)}, 0.01f);
    scene.fluid_blocks = {{glm::vec3(0.33f, 0.0f, 0.15f), glm::vec3(0.57f, 0.2f, 0.3f)}};
    PbfSolver solver(ctx(), scene);
    HandPool in_front(ctx(), [] {
        auto a = cloud({glm::vec3(0.1f, 0.06f, 0.25f), glm::vec3(0.2f, 0.14f, 0.27f)}, 600);
        auto b = cloud({glm::vec3(0.4f, 0.06f, 0.33f), glm::vec3(0.5f, 0.14f, 0.35f)}, 600);
        a.insert(a.end(), b.begin(), b.end());
        return a;
    }());
    HandPool inside(ctx(), cloud({glm::vec3(0.4f, 0.06f, 0.2f), glm::vec3(0.5f, 0.14f, 0.22f)}, 600));
    const ViewCamera camera = testing::tank_front_camera();
    const uint32_t width = testing::kTankPictureWidth;
    testing::for_each_method(ctx(), scene, solver.particle_count(), [&](Renderer& r, const MethodEntry& entry) {
        // A renderer never handed whitewater draws the method's own frame.
        const Image own = testing::tank_renderer(ctx(), scene, solver.particle_count(), entry)
                              ->render({solver.positions(), solver.particle_count()}, camera)
                              .color;
        FrameInput frame(solver.positions(), solver.particle_count());
        frame.whitewater = &in_front.view;
        const Image front = r.render(frame, camera).color;
        frame.whitewater = &inside.view;
        const Image behind = r.render(frame, camera).color;
        frame.whitewater = nullptr;
        const Image off = r.render(frame, camera).color;
        // Against the bright sky white foam changes little, but it is there.
        EXPECT_GT(changed(front, own, 0, width / 2), 20u) << "foam in the air is drawn";
        const double over_water = whiter(front, own, width / 2, width),
                     through_water = whiter(behind, own, width / 2, width);
        EXPECT_GT(over_water, 800.0) << "foam in front of the water is drawn white";
        EXPECT_GT(through_water, 0.0) << "bubbles are seen through the water";
        EXPECT_LT(through_water, 0.85 * over_water) << "the water in front of the bubbles dims them";
        EXPECT_EQ(off.rgba, own.rgba) << "without whitewater the frame is the method's own, bit for bit";
    });
}

TEST_F(WhitewaterTest, SolidsHideTheWhitewaterBehindThemInEveryMethod) {
    // A mesh block on the left and a static box on the right, each with foam behind it (hidden)
    // and foam in front of it (drawn over it). The water is a small pool at the back.
    auto dir = test_cli::temp_dir("whitewater_hidden");
    ASSERT_TRUE(geometry::write_obj(dir / "block.obj",
                                    geometry::make_box({glm::vec3(0.05f, 0.0f, 0.32f), glm::vec3(0.25f, 0.2f, 0.37f)}))
                    .ok());
    std::ofstream(dir / "scene.json")
        << R"({"name": "foam behind solids", "domain": {"min": [0, 0, 0], "max": [0.6, 0.3, 0.4]},
        "particle_spacing": 0.01, "fluid_blocks": [{"min": [0.25, 0, 0], "max": [0.35, 0.04, 0.06]}],
        "static_boxes": [{"min": [0.35, 0, 0.3], "max": [0.55, 0.2, 0.35]}], "obstacles": {"block": {"file": "block.obj"}}})";
    auto loaded = load_scene(dir / "scene.json");
    ASSERT_TRUE(loaded.ok()) << loaded.error();
    const Scene& scene = loaded.value();
    PbfSolver solver(ctx(), scene);
    // The solver's table holds the static box first (the renderers draw it from the domain).
    SolidsView solids{&solver.boundary_nodes(), {solver.params().solids + 1, solver.params().solids + 2}};
    auto two_clouds = [](float left_z, float right_z) {
        auto a = cloud({glm::vec3(0.1f, 0.06f, left_z), glm::vec3(0.2f, 0.14f, left_z + 0.02f)}, 600);
        auto b = cloud({glm::vec3(0.4f, 0.06f, right_z), glm::vec3(0.5f, 0.14f, right_z + 0.02f)}, 600);
        a.insert(a.end(), b.begin(), b.end());
        return a;
    };
    HandPool behind(ctx(), two_clouds(0.25f, 0.2f)), in_front(ctx(), two_clouds(0.38f, 0.37f));
    const ViewCamera camera = testing::tank_front_camera();
    const uint32_t width = testing::kTankPictureWidth;
    testing::for_each_method(ctx(), scene, solver.particle_count(), [&](Renderer& r, const MethodEntry&) {
        FrameInput frame(solver.positions(), solver.particle_count());
        frame.solids = &solids;
        const Image own = r.render(frame, camera).color;
        frame.whitewater = &behind.view;
        const Image hidden = r.render(frame, camera).color;
        frame.whitewater = &in_front.view;
        const Image shown = r.render(frame, camera).color;
        EXPECT_LE(changed(hidden, own, 0, width / 2), 2u) << "the mesh block hides the foam behind it";
        EXPECT_LE(changed(hidden, own, width / 2, width), 2u) << "the static box hides the foam behind it";
        EXPECT_GT(whiter(shown, own, 0, width / 2), 800.0) << "foam in front of the mesh block is drawn over it";
        EXPECT_GT(whiter(shown, own, width / 2, width), 800.0) << "foam in front of the static box is drawn over it";
    });
}

/// A PLY file's vertex count and the bytes after its header.
std::pair<size_t, size_t> ply_vertices(const std::filesystem::path& path) {
    const std::string text = test_cli::read_file(path);
    const size_t at = text.find("element vertex "), end = text.find("end_header\n");
    if (at == std::string::npos || end == std::string::npos) return {0, 0};
    return {std::stoul(text.substr(at + 15)), text.size() - end - 11};
}

TEST(WhitewaterRun, WhitewaterEveryWritesTheLiveParticlesAsPlyAndListsThem) {
    const auto dir = test_cli::temp_dir("whitewater_run");
    test_cli::write_file(dir / "scene.json",
                         R"({"name": "collision", "domain": {"min": [0, 0, 0], "max": [0.4, 0.3, 0.2]},
        "particle_spacing": 0.02, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.12, 0.12, 0.2], "velocity": [2, 0, 0]},
        {"min": [0.28, 0, 0], "max": [0.4, 0.12, 0.2], "velocity": [-2, 0, 0]}], "whitewater": {"k_trapped_air": 40000}})");
    const auto out = dir / "out";
    auto r = test_cli::run_aquaform("run " + (dir / "scene.json").string() +
                                    " --frames 11 --no-png --whitewater-every 5 --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::string stats = test_cli::read_file(out / "stats.csv");
    std::vector<std::string> rows;
    for (size_t at = 0, next; (next = stats.find('\n', at)) != std::string::npos; at = next + 1)
        rows.push_back(stats.substr(at, next - at));
    const auto column = [&](const std::string& name) {
        const std::string& header = rows.front();
        return size_t(std::count(header.begin(), header.begin() + header.find(name), ','));
    };
    const auto field = [&](size_t row, size_t col) {
        std::string line = rows[row];
        for (size_t c = 0; c < col; ++c) line = line.substr(line.find(',') + 1);
        return std::stoul(line.substr(0, line.find(',')));
    };
    const size_t spray = column("spray"), foam = column("foam"), bubbles = column("bubbles");
    for (int k = 0; k <= 2; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "whitewater_%04d.ply", k);
        ASSERT_TRUE(std::filesystem::exists(out / name)) << name << "\n" << r.output;
        const auto [vertices, body] = ply_vertices(out / name);
        const size_t row = 1 + 5 * k;  // frame 5k
        EXPECT_EQ(vertices, field(row, spray) + field(row, foam) + field(row, bubbles))
            << name << ": the frame's live count";
        EXPECT_EQ(body, vertices * 29) << name << ": position, velocity, kind, life";
        if (k > 0) EXPECT_GT(vertices, 0u) << name;
    }
    EXPECT_NE(test_cli::read_file(out / "exports.csv").find("whitewater_0002.ply,whitewater,10,"), std::string::npos);

    // whitewater.svg charts each kind alive over the run: a line per kind and their sum, a point
    // per frame, the last point of the sum at the last frame's live count.
    const std::string chart = test_cli::read_file(out / "whitewater.svg");
    for (const char* name : {">spray<", ">foam<", ">bubbles<", ">all<"})
        EXPECT_NE(chart.find(name), std::string::npos) << name << " is not in whitewater.svg's legend";
    EXPECT_EQ(chart.find("dropped"), std::string::npos) << "the pool was not full: no line of drops";
    size_t lines = 0;
    for (size_t at = 0; (at = chart.find("<polyline", at)) != std::string::npos; ++at) {
        const size_t begin = chart.find("points=\"", at) + 8, end = chart.find('"', begin);
        const std::string points = chart.substr(begin, end - begin);
        EXPECT_EQ(std::count(points.begin(), points.end(), ','), 11)
            << "a point per frame (11): " << points.substr(0, 80);
        ++lines;
    }
    EXPECT_EQ(lines, 4u) << "spray, foam, bubbles and their sum";

    // Without whitewater there is nothing to write: refused before any work, with the fix.
    test_cli::write_file(dir / "plain.json", R"({"name": "plain", "domain": {"min": [0, 0, 0], "max": [0.4, 0.3, 0.2]},
        "particle_spacing": 0.02, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.12, 0.12, 0.2]}]})");
    r = test_cli::run_aquaform("run " + (dir / "plain.json").string() +
                               " --frames 2 --no-png --whitewater-every 1 --out " + (dir / "o2").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--whitewater on"), std::string::npos) << r.output;

    // --whitewater-format: a format ParaView reads (tests/test_tools.cpp opens it), refused without
    // the files it is the format of, or with a format there is none of.
    for (const std::string& flags :
         {std::string("--whitewater-format vtp"), std::string("--whitewater-every 1 --whitewater-format obj")}) {
        r = test_cli::run_aquaform("run " + (dir / "scene.json").string() + " --frames 2 --no-png " + flags +
                                   " --out " + (dir / "o3").string());
        EXPECT_EQ(r.exit_code, 2) << flags << "\n" << r.output;
        EXPECT_NE(r.output.find(flags.find("obj") != std::string::npos ? "use ply (Blender) or vtp"
                                                                       : "give --whitewater-every K"),
                  std::string::npos)
            << r.output;
    }
}

TEST(WhitewaterRun, TheOldDiffuseFlagsAreTakenAndSaidToBeTheOldNames) {
    // --diffuse-every and --diffuse-format were the names of --whitewater-every and
    // --whitewater-format: still taken, said once to be the old names; beside the new, refused.
    const auto dir = test_cli::temp_dir("whitewater_old_flags");
    test_cli::write_file(dir / "scene.json",
                         R"({"name": "collision", "domain": {"min": [0, 0, 0], "max": [0.4, 0.3, 0.2]},
        "particle_spacing": 0.02, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.12, 0.12, 0.2], "velocity": [2, 0, 0]},
        {"min": [0.28, 0, 0], "max": [0.4, 0.12, 0.2], "velocity": [-2, 0, 0]}], "whitewater": {"k_trapped_air": 40000}})");
    const std::string run = "run '" + (dir / "scene.json").string() + "' --frames 5 --no-png ";
    const auto out = dir / "out";
    const std::vector<std::pair<std::string, std::string>> both_given = {
        {"--diffuse-every 2 --whitewater-every 2",
         "--diffuse-every is the old name of --whitewater-every; give --whitewater-every alone"},
        {"--whitewater-every 2 --diffuse-format vtp --whitewater-format vtp",
         "--diffuse-format is the old name of --whitewater-format; give --whitewater-format alone"}};
    for (const auto& [flags, fix] : both_given) {
        const auto both = test_cli::run_aquaform_split(run + flags + " --out '" + out.string() + "'", dir, 120);
        EXPECT_EQ(both.exit_code, 2) << flags << "\n" << both.err;
        EXPECT_NE(both.err.find(fix), std::string::npos) << flags << "\n" << both.err;
        EXPECT_FALSE(std::filesystem::exists(out / "stats.csv")) << "refused before any work: " << flags;
    }
    // A bad value given with the old name: said to be the old name, then refused by the new one.
    const auto bad = test_cli::run_aquaform_split(run + "--diffuse-every 0 --out '" + out.string() + "'", dir, 120);
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    const size_t said = bad.err.find("aquaform run: --diffuse-every is the old name of --whitewater-every");
    EXPECT_NE(said, std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("aquaform run: --whitewater-every must be a whole number", said), std::string::npos)
        << bad.err;

    // The old names alone work, write the new files and say so, once each; the files an earlier
    // version wrote under the old names go as an earlier run's do.
    std::filesystem::create_directories(out);
    test_cli::write_file(out / "diffuse_0003.ply", "ply\n");
    test_cli::write_file(out / "diffuse.pvd", "<VTKFile/>\n");
    const auto old = test_cli::run_aquaform_split(
        run + "--diffuse-every 2 --diffuse-format vtp --out '" + out.string() + "'", dir, 300);
    ASSERT_EQ(old.exit_code, 0) << old.err;
    for (const std::string said :
         {"aquaform run: --diffuse-every is the old name of --whitewater-every; give --whitewater-every 2",
          "aquaform run: --diffuse-format is the old name of --whitewater-format; give --whitewater-format vtp"}) {
        const size_t at = old.err.find(said);
        EXPECT_NE(at, std::string::npos) << old.err;
        EXPECT_EQ(old.err.find(said.substr(0, 40), at + 1), std::string::npos) << "said once: " << old.err;
    }
    for (const char* name : {"whitewater_0000.vtp", "whitewater_0002.vtp", "whitewater.pvd"})
        EXPECT_TRUE(std::filesystem::exists(out / name)) << name;
    for (const auto& entry : std::filesystem::directory_iterator(out))
        EXPECT_EQ(entry.path().filename().string().find("diffuse"), std::string::npos) << entry.path();
    EXPECT_NE(test_cli::read_file(out / "exports.csv").find("whitewater_0001.vtp,whitewater,2,"), std::string::npos);
    // The new names say nothing of the old.
    const auto now = test_cli::run_aquaform_split(run + "--whitewater-every 2 --out '" + out.string() + "'", dir, 300);
    ASSERT_EQ(now.exit_code, 0) << now.err;
    EXPECT_EQ(now.err.find("old name"), std::string::npos) << now.err;
    std::filesystem::remove_all(dir);
}

TEST(WhitewaterRun, TwoRunsWriteTheSameBytes) {
    // The pool's slots go to whichever invocation's atomicAdd comes first, so the same particles
    // sit in other slots from run to run; the files list them in an order of their own values.
    const auto dir = test_cli::temp_dir("whitewater_same_bits");
    test_cli::write_file(dir / "scene.json",
                         R"({"name": "collision", "domain": {"min": [0, 0, 0], "max": [0.4, 0.3, 0.2]},
        "particle_spacing": 0.02, "fluid_blocks": [{"min": [0, 0, 0], "max": [0.12, 0.12, 0.2], "velocity": [2, 0, 0]},
        {"min": [0.28, 0, 0], "max": [0.4, 0.12, 0.2], "velocity": [-2, 0, 0]}], "whitewater": {"k_trapped_air": 40000}})");
    for (const char* run : {"a", "b"}) {
        auto r = test_cli::run_aquaform("run " + (dir / "scene.json").string() +
                                        " --frames 9 --no-png --whitewater-every 4 "
                                        "--ply-every 8 --out " +
                                        (dir / run).string());
        ASSERT_EQ(r.exit_code, 0) << r.output;
    }
    for (const char* name : {"whitewater_0001.ply", "whitewater_0002.ply", "particles_0001.ply"}) {
        const std::string a = test_cli::read_file(dir / "a" / name), b = test_cli::read_file(dir / "b" / name);
        EXPECT_GT(a.size(), 300u) << name << " holds particles";
        EXPECT_TRUE(a == b) << name << " differs between two runs of one scene";
    }
}

TEST(WhitewaterScene, TheSectionIsCheckedWithTheFix) {
    const auto error_of = [](const std::string& text) {
        try {
            read_whitewater(nlohmann::json::parse(text));
        } catch (const json_fields::Invalid& e) {
            return e.message;
        }
        return std::string();
    };
    EXPECT_NE(error_of(R"({"lifetme": [1, 2]})").find("lifetime"), std::string::npos) << "a typo names the key meant";
    EXPECT_NE(error_of(R"({"lifetime": [3, 2]})").find("high end"), std::string::npos);
    EXPECT_NE(error_of(R"({"trapped_air": 5})").find("range [low, high]"), std::string::npos);
    EXPECT_NE(error_of(R"({"spray_below": 30, "bubble_above": 20})").find("foam lies between"), std::string::npos);
    EXPECT_NE(error_of(R"({"capacity": -1})").find("whitewater.capacity"), std::string::npos);
    EXPECT_NE(error_of(R"({"enabled": "yes"})").find("true or false"), std::string::npos);
    EXPECT_EQ(error_of(R"({"enabled": true, "capacity": 1000, "lifetime": [1, 3]})"), "");
    // The pool follows the fluid, within the device's memory.
    WhitewaterSettings s;
    EXPECT_EQ(whitewater_capacity(s, 100000, uint64_t(64) << 30), 400000u);
    EXPECT_EQ(whitewater_capacity(s, 1000, uint64_t(64) << 30), 65536u);
    EXPECT_EQ(whitewater_capacity(s, 100000000, uint64_t(1) << 30), (uint64_t(1) << 30) / 16 / 64);
    s.capacity = 77;
    EXPECT_EQ(whitewater_capacity(s, 100000, 1 << 30), 77u);
}

}  // namespace
}  // namespace aquaform
