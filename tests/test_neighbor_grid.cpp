// The GPU neighbour grid against brute force: the sort is a Morton-ordered permutation and
// the in-place query returns exactly the brute-force neighbour sets for hard distributions.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <tuple>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "grid/neighbor_grid.h"
#include "shaders/shared/grid/morton.h"
#include "sim/pbf_reference.h"
#include "tests/gpu_test.h"

namespace aquaform {
namespace {

constexpr float kCell = 0.25f;  // a power of two: boundary positions and distances are exact
const glm::vec3 kMin(0.0f), kMax(4.0f, 2.0f, 1.5f);

struct GridResult {
    std::vector<uint32_t> order, keys, cell_start, counts, lists;
    uint32_t capacity = 0;
    GridGeometry geometry;
};

class NeighborGridTest : public testing::GpuTest {
protected:
    GridResult build_and_query(const std::vector<glm::vec4>& positions, uint32_t capacity) {
        auto geometry = grid_for_domain(kMin, kMax, kCell);
        EXPECT_TRUE(geometry.ok());
        gpu::BufferSet buffers(ctx());
        const uint32_t n = static_cast<uint32_t>(positions.size());
        NeighborGrid grid(ctx(), buffers, geometry.value(), n);
        gpu::Buffer& pos = buffers.add("positions", n * sizeof(glm::vec4));
        gpu::Buffer& counts = buffers.add("counts", n * 4);
        gpu::Buffer& lists = buffers.add("lists", uint64_t(n) * capacity * 4);
        gpu::upload(ctx(), pos, positions.data(), n * sizeof(glm::vec4));
        ctx().submit_and_wait([&](VkCommandBuffer cmd) {
            grid.build(cmd, pos, n, nullptr);
            grid.record_list_neighbors(cmd, pos, n, kCell, capacity, counts, lists);
        });
        GridResult r;
        r.geometry = geometry.value();
        r.capacity = capacity;
        r.order = gpu::download_vector<uint32_t>(ctx(), grid.order(), n);
        r.keys = gpu::download_vector<uint32_t>(ctx(), grid.keys(), n);
        r.cell_start = gpu::download_vector<uint32_t>(ctx(), grid.cell_start(), r.geometry.cell_count() + 1);
        r.counts = gpu::download_vector<uint32_t>(ctx(), counts, n);
        r.lists = gpu::download_vector<uint32_t>(ctx(), lists, uint64_t(n) * capacity);
        return r;
    }

    /// The solver's per-step lists (record_neighbor_lists) of `positions` put in the grid's
    /// order first, as the solver keeps them: the sorted positions, counts and decoded lists.
    struct StepLists {
        std::vector<glm::vec4> sorted;
        std::vector<uint32_t> counts;
        std::vector<std::vector<uint32_t>> lists;  // the stored entries, at most the capacity
    };
    StepLists step_lists(const std::vector<glm::vec4>& positions, uint32_t capacity) {
        auto geometry = grid_for_domain(kMin, kMax, kCell);
        EXPECT_TRUE(geometry.ok());
        gpu::BufferSet buffers(ctx());
        const uint32_t n = static_cast<uint32_t>(positions.size());
        NeighborGrid grid(ctx(), buffers, geometry.value(), n, "grid", capacity);
        gpu::Buffer& pos = buffers.add("positions", n * sizeof(glm::vec4));
        gpu::upload(ctx(), pos, positions.data(), n * sizeof(glm::vec4));
        ctx().submit_and_wait([&](VkCommandBuffer cmd) { grid.build(cmd, pos, n, nullptr); });
        StepLists r;
        for (uint32_t i : gpu::download_vector<uint32_t>(ctx(), grid.order(), n)) r.sorted.push_back(positions[i]);
        gpu::upload(ctx(), pos, r.sorted.data(), n * sizeof(glm::vec4));
        ctx().submit_and_wait([&](VkCommandBuffer cmd) { grid.record_neighbor_lists(cmd, pos, n, kCell, nullptr); });
        r.counts = gpu::download_vector<uint32_t>(ctx(), grid.neighbor_count(), n);
        // Entries 4g..4g+3 of particle i sit at uvec4 g * n + i (shared/grid/grid_layout.h).
        const auto entries = gpu::download_vector<uint32_t>(ctx(), grid.neighbors(), uint64_t(n) * capacity);
        r.lists.resize(n);
        for (uint32_t i = 0; i < n; ++i)
            for (uint32_t k = 0; k < std::min(r.counts[i], capacity); ++k)
                r.lists[i].push_back(entries[(uint64_t(k / 4) * n + i) * 4 + k % 4]);
        return r;
    }

    void expect_sets_match_brute_force(const std::vector<glm::vec4>& positions, uint32_t capacity) {
        GridResult r = build_and_query(positions, capacity);
        auto expected = brute_force_neighbors(positions, kCell);
        int mismatches = 0;
        for (uint32_t i = 0; i < positions.size() && mismatches < 5; ++i) {
            ASSERT_LE(r.counts[i], capacity) << "raise the test's list capacity";
            std::vector<uint32_t> got(r.lists.begin() + uint64_t(i) * capacity,
                                      r.lists.begin() + uint64_t(i) * capacity + r.counts[i]);
            std::sort(got.begin(), got.end());
            if (got != expected[i]) {
                ++mismatches;
                ADD_FAILURE() << "particle " << i << " at (" << positions[i].x << ", " << positions[i].y << ", "
                              << positions[i].z << "): GPU found " << got.size() << " neighbours, brute force "
                              << expected[i].size();
            }
        }
    }
};

std::vector<glm::vec4> uniform_random(uint32_t n, glm::vec3 lo, glm::vec3 hi, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<glm::vec4> p(n);
    for (auto& x : p) x = glm::vec4(lo + (hi - lo) * glm::vec3(u(rng), u(rng), u(rng)), 0.0f);
    return p;
}

TEST_F(NeighborGridTest, SortIsAPermutationInMortonOrder) {
    auto positions = uniform_random(3000, kMin, kMax, 1);
    GridResult r = build_and_query(positions, 64);
    const uint32_t n = static_cast<uint32_t>(positions.size());
    std::vector<uint32_t> sorted = r.order;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i) << "order is not a permutation";

    const glm::vec4 oc(r.geometry.origin, r.geometry.cell_size);
    const glm::uvec4 dims(r.geometry.dims, r.geometry.cell_count());
    uint32_t previous_code = 0;
    for (uint32_t s = 0; s < n; ++s) {
        const glm::ivec3 c = shader::grid_cell(glm::vec3(positions[r.order[s]]), oc, dims);
        const uint32_t code = shader::morton_encode(glm::uvec3(c));
        ASSERT_GE(code, previous_code) << "sorted position " << s << " breaks Z-order";
        previous_code = code;
        const uint32_t rank = r.keys[r.order[s]];
        ASSERT_GE(s, r.cell_start[rank]);
        ASSERT_LT(s, r.cell_start[rank + 1]) << "cell_start does not bracket sorted position " << s;
    }
    EXPECT_EQ(r.cell_start.back(), n);
}

// The scatter's atomics order a cell's particles as the device ran them; the stable pass must
// give the same order whatever that was (ascending index within a cell), so that every sum over
// neighbours is the same on every run. The arrival order is scrambled by hand here because a
// device may happen to run the atomics in index order.
TEST_F(NeighborGridTest, ACellsParticlesComeInIndexOrderWhateverOrderTheAtomicsTook) {
    auto positions = uniform_random(3000, kMin, kMax, 5);
    // plus a degenerate cell: more particles than the stable pass ranks (they keep arrival order)
    for (uint32_t k = 0; k < shader::GRID_STABLE_MAX_CELL + 40; ++k) positions.emplace_back(0.01f, 0.01f, 0.01f, 0.0f);
    auto geometry = grid_for_domain(kMin, kMax, kCell);
    ASSERT_TRUE(geometry.ok());
    gpu::BufferSet buffers(ctx());
    const uint32_t n = static_cast<uint32_t>(positions.size());
    NeighborGrid grid(ctx(), buffers, geometry.value(), n);
    gpu::Buffer& pos = buffers.add("positions", n * sizeof(glm::vec4));
    gpu::upload(ctx(), pos, positions.data(), n * sizeof(glm::vec4));
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { grid.build(cmd, pos, n, nullptr); });
    const auto keys = gpu::download_vector<uint32_t>(ctx(), grid.keys(), n);
    const auto start = gpu::download_vector<uint32_t>(ctx(), grid.cell_start(), geometry.value().cell_count() + 1);
    auto check = [&](const char* when, std::vector<uint32_t>& order) {
        order = gpu::download_vector<uint32_t>(ctx(), grid.order(), n);
        std::vector<uint32_t> sorted = order;
        std::sort(sorted.begin(), sorted.end());
        for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i) << when << ": order is not a permutation";
        size_t cells_checked = 0;
        for (size_t c = 0; c + 1 < start.size(); ++c) {
            if (start[c + 1] - start[c] < 2 || start[c + 1] - start[c] > shader::GRID_STABLE_MAX_CELL) continue;
            ++cells_checked;
            for (uint32_t s = start[c] + 1; s < start[c + 1]; ++s)
                ASSERT_LT(order[s - 1], order[s]) << when << ": cell " << c << " is not in index order";
        }
        EXPECT_GT(cells_checked, 100u);
    };
    std::vector<uint32_t> built, reranked;
    check("after build", built);
    if (HasFatalFailure()) return;
    // Reverse every cell's arrival order and rank again.
    auto arrival = gpu::download_vector<uint32_t>(ctx(), grid.arrival(), n);
    for (size_t c = 0; c + 1 < start.size(); ++c)
        std::reverse(arrival.begin() + start[c], arrival.begin() + start[c + 1]);
    gpu::upload(ctx(), grid.arrival(), arrival.data(), n * 4);
    ctx().submit_and_wait([&](VkCommandBuffer cmd) { grid.record_stable_order(cmd, n); });
    check("after scrambling the arrival order", reranked);
    if (HasFatalFailure()) return;
    for (uint32_t s = 0; s < n; ++s) {
        if (start[keys[built[s]] + 1] - start[keys[built[s]]] > shader::GRID_STABLE_MAX_CELL) continue;
        ASSERT_EQ(built[s], reranked[s]) << "sorted place " << s << " depends on the arrival order";
    }
}

TEST_F(NeighborGridTest, RandomMatchesBruteForce) {
    expect_sets_match_brute_force(uniform_random(2500, kMin, kMax, 2), 96);
}

TEST_F(NeighborGridTest, ClusteredMatchesBruteForce) {
    std::mt19937 rng(3);
    std::normal_distribution<float> g(0.0f, 0.08f);
    std::vector<glm::vec4> p;
    const glm::vec3 centres[] = {{0.5f, 0.5f, 0.5f}, {2.0f, 1.0f, 0.75f}, {3.9f, 0.1f, 1.4f}};
    for (const auto& c : centres)
        for (int i = 0; i < 600; ++i) p.push_back(glm::vec4(c + glm::vec3(g(rng), g(rng), g(rng)), 0.0f));
    expect_sets_match_brute_force(p, 1024);
}

TEST_F(NeighborGridTest, AllInOneCellMatchesBruteForce) {
    auto p = uniform_random(400, glm::vec3(1.01f, 1.01f, 0.51f), glm::vec3(1.24f, 1.24f, 0.74f), 4);
    GridResult r = build_and_query(p, 512);
    for (uint32_t k : r.keys) ASSERT_EQ(k, r.keys[0]) << "the test points must share one cell";
    expect_sets_match_brute_force(p, 512);
}

TEST_F(NeighborGridTest, OnCellBoundariesMatchesBruteForce) {
    // Points exactly on cell faces, edges and corners, plus half-cell offsets: distances of
    // exactly one radius must be excluded on both sides, and floor() must not misplace a point.
    std::vector<glm::vec4> p;
    for (int z = 0; z <= 6; ++z)
        for (int y = 0; y <= 8; ++y)
            for (int x = 0; x <= 16; ++x) {
                glm::vec3 q = glm::vec3(x, y, z) * kCell;
                if (glm::all(glm::lessThanEqual(q, kMax))) p.push_back(glm::vec4(q, 0.0f));
                if (x % 3 == 0) p.push_back(glm::vec4(q + glm::vec3(0.5f * kCell, 0.0f, 0.0f), 0.0f));
            }
    expect_sets_match_brute_force(p, 128);
}

TEST_F(NeighborGridTest, OutOfDomainMatchesBruteForce) {
    auto p = uniform_random(1500, kMin, kMax, 5);
    auto outside = uniform_random(300, glm::vec3(-3.0f, -2.0f, -1.0f), glm::vec3(7.0f, 4.0f, 3.0f), 6);
    p.insert(p.end(), outside.begin(), outside.end());
    p.push_back(glm::vec4(-1.0e6f, 5.0f, 0.5f, 0.0f));        // very far away
    p.push_back(glm::vec4(kMax.x + 0.1f, 1.0f, 0.7f, 0.0f));  // just outside, with neighbours inside
    p.push_back(glm::vec4(kMax.x - 0.05f, 1.0f, 0.7f, 0.0f));
    expect_sets_match_brute_force(p, 256);
}

TEST_F(NeighborGridTest, StepListsHoldEveryNeighbourOfCrowdedCells) {
    // A sparse background with two crowded cells: 60 particles in one (more than one word of
    // candidate bits, 32) and 300 in another (more neighbours than the list holds). The count is
    // the true one wherever the list has room (a crowded cell is no reason to scan cells), the
    // stored entries are the brute-force set, and beyond the capacity the count still says so,
    // so that visits scan the cells.
    auto p = uniform_random(1200, kMin, kMax, 8);
    auto crowded = uniform_random(60, glm::vec3(1.0f, 1.0f, 0.5f), glm::vec3(1.25f, 1.25f, 0.75f), 9);
    auto overfull = uniform_random(300, glm::vec3(3.0f, 0.5f, 0.75f), glm::vec3(3.25f, 0.75f, 1.0f), 10);
    p.insert(p.end(), crowded.begin(), crowded.end());
    p.insert(p.end(), overfull.begin(), overfull.end());
    const uint32_t capacity = 128;
    StepLists r = step_lists(p, capacity);
    auto expected = brute_force_neighbors(r.sorted, kCell);
    auto cell_of = [](glm::vec4 x) { return glm::ivec3(glm::floor(glm::vec3(x) / kCell)); };
    std::map<std::tuple<int, int, int>, uint32_t> per_cell;
    for (const glm::vec4& x : r.sorted) {
        const glm::ivec3 c = cell_of(x);
        ++per_cell[{c.x, c.y, c.z}];
    }
    uint32_t listed = 0, overflowing = 0, in_crowded_cells = 0;
    for (uint32_t i = 0; i < p.size(); ++i) {
        const uint32_t truth = uint32_t(expected[i].size());
        if (truth > capacity) {
            ++overflowing;
            ASSERT_GT(r.counts[i], capacity) << "particle " << i << " has " << truth << " neighbours";
            continue;
        }
        ASSERT_EQ(r.counts[i], truth) << "particle " << i;
        std::vector<uint32_t> got = r.lists[i];
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, expected[i]) << "particle " << i;
        ++listed;
        const glm::ivec3 c = cell_of(r.sorted[i]);
        if (per_cell[{c.x, c.y, c.z}] > 32) ++in_crowded_cells;
    }
    EXPECT_GE(in_crowded_cells, 60u) << "listed particles in cells beyond one word of candidate bits (32)";
    EXPECT_GT(overflowing, 10u) << "some particles must exceed the capacity";
    EXPECT_GT(listed, 1200u);
}

}  // namespace
}  // namespace aquaform
