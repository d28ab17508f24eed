// bench/bench_sim.h: what `aquaform bench sim` measures, checked on a small dam break; and the
// byte model beside its times (grid/grid_traffic.h, sim/pbf_traffic.h), checked against the
// passes a step records and the lists it fills.
#include <cmath>
#include <random>
#include <set>

#include "bench/bench_scenes.h"
#include "bench/bench_sim.h"
#include "gpu/timer.h"
#include "sim/pbf_solver.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

using testing::GpuTest;

class BenchSimTest : public GpuTest {};

TEST_F(BenchSimTest, MeasuresTheSolverOnADamBreakOfTheAskedSize) {
    const study::SolverBenchRecord r = study::measure_solver(ctx(), 2000, {2, 2, 2, 2});
    // bench_scene rounds the column to whole spacings: within a few per cent of the target.
    EXPECT_NEAR(double(r.particles), 2000.0, 400.0);
    EXPECT_EQ(r.iterations, 2u);
    EXPECT_GT(r.ms_per_step, 0.0);
    EXPECT_NEAR(r.steps_per_s, 1000.0 / r.ms_per_step, 1e-9);
    // The neighbour search is the sum of its passes, and only part of a step.
    double search = 0.0;
    for (const char* pass : study::kNeighborSearchPasses) {
        ASSERT_TRUE(r.ms_per_pass.count(pass)) << pass;
        search += r.ms_per_pass.at(pass);
    }
    EXPECT_NEAR(r.neighbor_search_ms, search, 1e-9);
    EXPECT_GT(r.ms_per_pass.at("sim_lambda"), 0.0);
    EXPECT_LT(r.neighbor_search_ms, r.ms_per_step);
    EXPECT_GT(r.grid_cells, 0u);
    EXPECT_GT(r.gpu_bytes_per_particle, 100.0);  // positions, velocities, grid entries, neighbour lists...
    // The byte model covers every timed pass, and its floor is its unique bytes at the bandwidth.
    ASSERT_EQ(r.traffic.size(), r.ms_per_pass.size());
    for (const PassTraffic& p : r.traffic) {
        EXPECT_TRUE(r.ms_per_pass.count(p.name)) << p.name << " is modelled but not timed";
        EXPECT_GT(p.unique_bytes, 0u) << p.name;
        EXPECT_GE(p.bytes, p.unique_bytes) << p.name;
    }
    EXPECT_EQ(r.counts.particles, r.particles);
    EXPECT_DOUBLE_EQ(r.bandwidth_gbps, study::kH200CopyGbps);
    EXPECT_NEAR(r.memory_floor_ms(), double(r.unique_bytes_per_step()) / (study::kH200CopyGbps * 1e9) * 1e3, 1e-12);
    EXPECT_GT(r.all_loads_floor_ms(), r.memory_floor_ms());
    const nlohmann::json j = study::to_json(r);
    for (const char* key :
         {"bytes_per_pass", "unique_bytes_per_pass", "memory_floor_ms", "grid_counts", "neighbor_visits_per_pass"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["bytes_per_pass"].size(), r.ms_per_pass.size());
}

TEST_F(BenchSimTest, WarmsUpAsARunStepsAndTimesTheRulesStep) {
    // 16k particles, 2 iterations: the column compresses past the density bound in its first
    // frames, and the time-step rule takes more than the scene's 2 steps a frame. Fixed steps
    // (what the warm-up was) would time the scene's 2, whatever the state.
    const study::SolverBenchRecord r = study::measure_solver(ctx(), 16000, {2, 1, 1, 20});
    EXPECT_GT(r.steps_per_frame, 2u) << "the timed steps are the time-step rule's, not the scene's least";
    EXPECT_GE(r.warmup_steps, 20u);
    EXPECT_EQ(r.list_overflow_fraction, 0.0) << "a state the rule keeps: no particle past its list";
}

// Counts of a small state: `scale` copies of a 1000-particle, 4000-cell grid with 30 listed
// neighbours a particle, none past its list.
GridCounts synthetic_counts(uint64_t scale) {
    GridCounts c;
    c.particles = 1000 * scale;
    c.cells = 4000 * scale;
    c.occupied_cells = 200 * scale;
    c.capacity = 64;
    c.cell_visits = 27000 * scale;
    c.candidates = 150000 * scale;
    c.cell_member_reads = 5000 * scale;
    c.list_entries = c.neighbor_pairs = 30000 * scale;
    c.list_texels = c.stored_texels = 8000 * scale;
    return c;
}

const PassTraffic& pass(const std::vector<PassTraffic>& passes, const std::string& name) {
    for (const PassTraffic& p : passes)
        if (p.name == name) return p;
    throw std::runtime_error("no pass " + name + " in the model");
}

/// The byte model of a step the solver then runs under a timer: every pass it times is
/// modelled, and nothing else.
std::vector<PassTraffic> timed_step_model(gpu::Context& ctx, PbfSolver& solver) {
    gpu::GpuTimer timer(ctx);
    solver.run_steps(1, &timer);
    std::set<std::string> timed, modelled;
    for (const auto& [name, ms] : timer.totals_ms()) timed.insert(name);
    const std::vector<PassTraffic> model = solver.traffic_per_pass();
    for (const PassTraffic& p : model) modelled.insert(p.name);
    EXPECT_EQ(timed, modelled);
    return model;
}

TEST(TrafficModel, ALambdaVisitLoadsItsListGroupAndTheNeighboursPosition) {
    // By hand, from pbf_lambda.comp: per particle its count (4 B), its position (16 B), q and the
    // density stored (16 + 4 B); per list group 16 B; per listed neighbour its position (16 B),
    // which the pass reads at its own particle too, so adds nothing unique.
    const GridCounts c = synthetic_counts(1);
    const PassTraffic& lambda = pass(step_traffic(c, {1, true, true}), "sim_lambda");
    EXPECT_EQ(lambda.bytes, 1000u * (4 + 16 + 16 + 4) + 8000u * 16 + 30000u * 16);
    EXPECT_EQ(lambda.unique_bytes, 1000u * (4 + 16 + 16 + 4) + 8000u * 16);
    EXPECT_EQ(lambda.neighbor_visits, 30000u);
    // The list fill loads every candidate's position and stores the groups.
    const PassTraffic& lists = pass(step_traffic(c, {1, true, true}), "sim_neighbor_lists");
    EXPECT_GE(lists.bytes, 150000u * 16 + 8000u * 16);
    EXPECT_EQ(lists.neighbor_visits, 150000u);
}

TEST(TrafficModel, ScalesWithTheStateAndSumsToItsTotal) {
    const std::vector<PassTraffic> one = step_traffic(synthetic_counts(1), {4, true, true});
    const std::vector<PassTraffic> two = step_traffic(synthetic_counts(2), {4, true, true});
    ASSERT_EQ(one.size(), two.size());
    uint64_t sum = 0, unique = 0;
    for (size_t i = 0; i < one.size(); ++i) {
        EXPECT_EQ(one[i].name, two[i].name);
        EXPECT_GT(one[i].bytes, 0u) << one[i].name;
        sum += one[i].bytes;
        unique += one[i].unique_bytes;
        // Twice the particles, cells and entries: twice the bytes (but for cell_start's one entry
        // past the cells, and the scan's block sums, which round).
        const double tolerance = one[i].name == "sim_grid_scan" ? 0.01 : 1e-3;
        EXPECT_NEAR(double(two[i].bytes) / double(one[i].bytes), 2.0, tolerance) << one[i].name;
        EXPECT_NEAR(double(two[i].unique_bytes) / double(one[i].unique_bytes), 2.0, tolerance) << one[i].name;
    }
    EXPECT_EQ(total_bytes(one), sum);
    EXPECT_EQ(total_unique_bytes(one), unique);
    // Twice the list entries alone: only the passes that visit neighbours read more.
    GridCounts fuller = synthetic_counts(1);
    fuller.list_entries *= 2;
    const std::vector<PassTraffic> more = step_traffic(fuller, {4, true, true});
    for (size_t i = 0; i < one.size(); ++i)
        EXPECT_EQ(more[i].bytes > one[i].bytes, one[i].neighbor_visits > 0 && one[i].name != "sim_neighbor_lists")
            << one[i].name;
}

TEST(TrafficModel, TheConstraintPassesRunOncePerIteration) {
    const std::vector<PassTraffic> four = step_traffic(synthetic_counts(1), {4, true, true});
    const std::vector<PassTraffic> eight = step_traffic(synthetic_counts(1), {8, true, true});
    ASSERT_EQ(four.size(), eight.size());
    for (size_t i = 0; i < four.size(); ++i) {
        const bool constraint = four[i].name == "sim_lambda" || four[i].name == "sim_correct";
        EXPECT_EQ(four[i].runs, constraint ? 4u : 1u) << four[i].name;
        // The last correction's velocity update (loads x, stores v and x for p) comes once a step.
        const uint64_t update = four[i].name == "sim_correct" ? 32u * 1000 : 0;
        EXPECT_EQ(eight[i].bytes - update, (four[i].bytes - update) * (constraint ? 2 : 1)) << four[i].name;
        EXPECT_EQ(eight[i].unique_bytes - update, (four[i].unique_bytes - update) * (constraint ? 2 : 1))
            << four[i].name;
    }
    // Passes a scene turns off are not modelled.
    std::set<std::string> names;
    for (const PassTraffic& p : step_traffic(synthetic_counts(1), {4, false, false})) names.insert(p.name);
    EXPECT_FALSE(names.count("sim_xsph_curl") || names.count("sim_vorticity"));
    EXPECT_EQ(names.size(), four.size() - 2);
}

TEST(TrafficModel, CountsCellsCandidatesAndListsFromTheGridsTables) {
    // A row of 4 cells: 2 particles in cell 0, 1 in cell 1, none in cell 2, 3 in cell 3.
    GridGeometry g;
    g.dims = glm::uvec3(4, 1, 1);
    const std::vector<uint32_t> rank = morton_rank_table(g);
    const uint32_t members[4] = {2, 1, 0, 3};
    std::vector<uint32_t> start(5, 0);
    for (uint32_t cell = 0; cell < 4; ++cell) start[rank[cell] + 1] = members[cell];
    for (uint32_t r = 0; r < 4; ++r) start[r + 1] += start[r];
    const std::vector<uint32_t> list_cell = {0, 0, 1, 3, 3, 3};
    const std::vector<uint32_t> counts = {1, 2, 2, 2, 2, 9};  // the last is past a capacity of 8
    const GridCounts c = count_grid_work(g, 8, start, counts, list_cell);
    EXPECT_EQ(c.particles, 6u);
    EXPECT_EQ(c.occupied_cells, 3u);
    EXPECT_EQ(c.cell_visits, 2u * 2 + 3 + 3u * 2);      // cells 0 and 3 have one neighbour cell in the grid
    EXPECT_EQ(c.candidates, 2u * 3 + 1u * 3 + 3u * 3);  // cells 0+1, 0+1+2, 2+3
    EXPECT_EQ(c.cell_member_reads, 4u + 1 + 9);
    EXPECT_EQ(c.list_entries, 9u);
    EXPECT_EQ(c.list_texels, 5u);
    EXPECT_EQ(c.stored_texels, 5u + 2);  // the overflowing list stores its first 8 entries
    EXPECT_EQ(c.overflow_particles, 1u);
    EXPECT_EQ(c.overflow_cell_visits, 2u);
    EXPECT_EQ(c.overflow_visits, 2u);  // the other particles of cells 2 and 3
    EXPECT_EQ(c.visits(), 11u);
    EXPECT_EQ(c.neighbor_pairs, 18u);
}

TEST_F(BenchSimTest, TheModelFollowsTheStepsPassesAndTheListsItFills) {
    PbfSolver solver(ctx(), study::bench_scene(2000, 2));
    // Jittered, at rest: the lists are of x itself (predicted positions at zero velocity), and
    // no pair sits at exactly the kernel radius.
    ParticleSnapshot s = solver.snapshot();
    std::mt19937 rng(36);
    std::uniform_real_distribution<float> jitter(-0.2f, 0.2f);
    const float spacing = solver.scene().particle_spacing;
    // Kept where collision keeps them (pbf_collide), so that the predicted positions are x.
    const float margin = solver.params().domain_min.w;
    const glm::vec3 lo = glm::vec3(solver.params().domain_min) + margin,
                    hi = glm::vec3(solver.params().domain_max) - margin;
    for (glm::vec4& x : s.x)
        x = glm::vec4(glm::clamp(glm::vec3(x) + glm::vec3(jitter(rng), jitter(rng), jitter(rng)) * spacing, lo, hi),
                      x.w);
    solver.set_state(s.x, std::vector<glm::vec4>(s.x.size(), glm::vec4(0.0f)));
    s = solver.snapshot();
    const GridCounts c = solver.grid_counts();
    // The true neighbour count, by brute force on the host.
    const float h2 = solver.params().h * solver.params().h;
    uint64_t below = 0, above = 0;
    for (size_t i = 0; i < s.x.size(); ++i)
        for (size_t j = 0; j < s.x.size(); ++j) {
            const glm::vec3 d = glm::vec3(s.x[i]) - glm::vec3(s.x[j]);
            below += i != j && glm::dot(d, d) < h2 * (1.0f - 1e-4f);
            above += i != j && glm::dot(d, d) < h2 * (1.0f + 1e-4f);
        }
    EXPECT_GE(c.neighbor_pairs, below);
    EXPECT_LE(c.neighbor_pairs, above);
    EXPECT_EQ(c.overflow_particles, 0u);
    EXPECT_EQ(c.list_entries, c.neighbor_pairs);
    // Candidates: each particle's 27 cells' members, binned on the host.
    const GridGeometry& g = solver.grid().geometry();
    std::vector<uint64_t> members(g.cell_count(), 0);
    for (const glm::vec4& x : s.x)
        ++members[shader::grid_linear(
            shader::grid_cell(glm::vec3(x), glm::vec4(g.origin, g.cell_size), glm::uvec4(g.dims, g.cell_count())),
            glm::uvec4(g.dims, g.cell_count()))];
    uint64_t candidates = 0;
    for (const glm::vec4& x : s.x) {
        const glm::ivec3 cell =
            shader::grid_cell(glm::vec3(x), glm::vec4(g.origin, g.cell_size), glm::uvec4(g.dims, g.cell_count()));
        for (int k = 0; k < 27; ++k) {
            const glm::ivec3 n = cell + glm::ivec3(k % 3, (k / 3) % 3, k / 9) - glm::ivec3(1);
            if (glm::all(glm::greaterThanEqual(n, glm::ivec3(0))) && glm::all(glm::lessThan(n, glm::ivec3(g.dims))))
                candidates += members[shader::grid_linear(n, glm::uvec4(g.dims, g.cell_count()))];
        }
    }
    EXPECT_EQ(c.candidates, candidates);
    const std::vector<PassTraffic> model = timed_step_model(ctx(), solver);
    EXPECT_EQ(model.front().name, "sim_predict");
    EXPECT_EQ(pass(model, "sim_lambda").runs, 2u);
    EXPECT_EQ(pass(model, "sim_lambda").neighbor_visits, 2 * solver.grid_counts().visits());
}

TEST_F(BenchSimTest, BothMethodsStartWithTheListsOfTheirStartPositions) {
    // At rest p = x + dt v = x, so PBF's start lists (of p) and DFSPH's (of x) are the same; DFSPH's
    // once listed its carried state, which the sort leaves in p, and counted nothing like them.
    Scene scene = study::bench_scene(2000, 2);
    PbfSolver pbf(ctx(), scene);
    scene.solver.method = PressureMethod::dfsph;
    PbfSolver dfsph(ctx(), scene);
    const GridCounts a = pbf.grid_counts(), b = dfsph.grid_counts();
    EXPECT_GT(a.list_entries, 10u * a.particles) << "the start lists hold the neighbours";
    EXPECT_EQ(b.list_entries, a.list_entries);
    EXPECT_EQ(b.neighbor_pairs, a.neighbor_pairs);
}

TEST_F(BenchSimTest, TheDfsphModelFollowsItsStepsPasses) {
    Scene scene = study::bench_scene(2000, 2);
    scene.solver.method = PressureMethod::dfsph;
    scene.solver.iterations = 3;
    scene.solver.divergence_iterations = 2;
    PbfSolver solver(ctx(), scene);
    const std::vector<PassTraffic> model = timed_step_model(ctx(), solver);
    // Each solve: its warm start's velocity pass, then a rate and a velocity pass per iteration.
    EXPECT_EQ(pass(model, "sim_dfsph_rate").runs, 3u + 2u);
    EXPECT_EQ(pass(model, "sim_dfsph_velocity").runs, 3u + 2u + 2u);
    EXPECT_EQ(pass(model, "sim_dfsph_factors").neighbor_visits, solver.grid_counts().visits());
    scene.solver.divergence_iterations = 0;  // off: no warm start of it either
    EXPECT_EQ(pass(step_traffic(solver.grid_counts(), step_shape(scene.solver)), "sim_dfsph_velocity").runs, 3u + 1u);
}

TEST(BenchSimExponent, IsTheSlopeOfLogTimeAgainstLogParticles) {
    std::vector<study::SolverBenchRecord> records(3);
    const double n[] = {1000, 2000, 8000};
    for (int i = 0; i < 3; ++i) {
        records[i].particles = uint32_t(n[i]);
        records[i].neighbor_search_ms = 0.5 * std::pow(n[i], 1.25);
    }
    EXPECT_NEAR(study::neighbor_search_exponent(records), 1.25, 1e-9);
    records.resize(1);
    EXPECT_TRUE(std::isnan(study::neighbor_search_exponent(records)));
}

}  // namespace
}  // namespace aquaform
