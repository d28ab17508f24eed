#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "grid/neighbor_grid.h"
#include "shaders/shared/grid/morton.h"

namespace aquaform {
namespace {

TEST(Morton, EncodeDecodeRoundTrip) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<uint32_t> coord(0, 1023);
    std::vector<glm::uvec3> cells = {{0, 0, 0}, {1023, 1023, 1023}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {512, 256, 1023}};
    for (int i = 0; i < 10000; ++i) cells.push_back({coord(rng), coord(rng), coord(rng)});
    for (const auto& c : cells) {
        const uint32_t code = shader::morton_encode(c);
        EXPECT_EQ(shader::morton_decode(code), c) << "cell " << c.x << "," << c.y << "," << c.z;
        EXPECT_LT(code, 1u << 30);
    }
}

TEST(Morton, InterleavesXLowest) {
    EXPECT_EQ(shader::morton_encode({1, 0, 0}), 1u);
    EXPECT_EQ(shader::morton_encode({0, 1, 0}), 2u);
    EXPECT_EQ(shader::morton_encode({0, 0, 1}), 4u);
    EXPECT_EQ(shader::morton_encode({2, 0, 0}), 8u);
    EXPECT_EQ(shader::morton_encode({3, 3, 3}), 63u);
}

TEST(Morton, RankTableIsAPermutationInZOrder) {
    // A long, thin grid (not a power of two on any axis), like a dam-break tank.
    GridGeometry g;
    g.dims = {37, 11, 6};
    const auto rank = morton_rank_table(g);
    ASSERT_EQ(rank.size(), g.cell_count());
    std::vector<uint32_t> by_rank(rank.size(), UINT32_MAX);
    for (uint32_t cell = 0; cell < rank.size(); ++cell) {
        ASSERT_LT(rank[cell], rank.size());
        ASSERT_EQ(by_rank[rank[cell]], UINT32_MAX) << "rank " << rank[cell] << " given twice";
        by_rank[rank[cell]] = cell;
    }
    auto code_of = [&](uint32_t cell) {
        return shader::morton_encode({cell % g.dims.x, (cell / g.dims.x) % g.dims.y, cell / (g.dims.x * g.dims.y)});
    };
    for (uint32_t r = 1; r < by_rank.size(); ++r) EXPECT_LT(code_of(by_rank[r - 1]), code_of(by_rank[r]));
}

TEST(Morton, GridRefusesDomainsBeyondTheCodeRange) {
    auto ok = grid_for_domain(glm::vec3(0.0f), glm::vec3(1.0f, 0.5f, 0.25f), 0.01f);
    ASSERT_TRUE(ok.ok()) << ok.error();
    EXPECT_EQ(ok.value().dims, glm::uvec3(102, 52, 27));
    auto too_long = grid_for_domain(glm::vec3(0.0f), glm::vec3(20.0f, 1.0f, 1.0f), 0.01f);
    ASSERT_FALSE(too_long.ok());
    EXPECT_NE(too_long.error().find("on x"), std::string::npos) << too_long.error();
    EXPECT_NE(too_long.error().find("particle_spacing"), std::string::npos) << too_long.error();
}

}  // namespace
}  // namespace aquaform
