#include "sim/pbf_traffic.h"

namespace aquaform {

namespace {

PassTraffic per_particle(const char* name, uint64_t particles, uint64_t bytes_each) {
    return {name, 1, particles * bytes_each, particles * bytes_each};
}

/// A pass over the neighbour lists: the loop's reads plus `own` bytes per particle (its own
/// loads and stores), run `runs` times a step.
PassTraffic neighbor_pass(const char* name, const GridCounts& c, uint32_t runs, uint64_t per_neighbor,
                          uint64_t neighbor_only, uint64_t own) {
    PassTraffic t = neighbor_loop_traffic(c, per_neighbor, neighbor_only);
    t.name = name;
    t.runs = runs;
    t.bytes = runs * (t.bytes + own * c.particles);
    t.unique_bytes = runs * (t.unique_bytes + own * c.particles);
    t.neighbor_visits *= runs;
    return t;
}

/// The velocity filters that end either solve's step (sim/velocity_filters.h).
void add_filters(std::vector<PassTraffic>& passes, const GridCounts& c, const StepShape& shape) {
    // pbf_xsph_curl: x_i, v_i; each neighbour's x, density, v; v_out and omega stored.
    if (shape.xsph) passes.push_back(neighbor_pass("sim_xsph_curl", c, 1, 16 + 4 + 16, 4, 16 + 16 + 16 + 16));
    // pbf_vorticity: x_i, omega_i, v loaded and stored; each neighbour's x, density, omega.
    if (shape.vorticity) passes.push_back(neighbor_pass("sim_vorticity", c, 1, 16 + 4 + 16, 4, 16 + 16 + 16 + 16));
}

/// A DFSPH step (sim/dfsph_pressure.h): the sort by x, the factors, both solves (each a warm
/// start's velocity pass and its iterations' rate and velocity passes), the advance.
std::vector<PassTraffic> dfsph_step_traffic(const GridCounts& c, const StepShape& shape) {
    const uint64_t n = c.particles;
    const std::vector<PassTraffic> grid = grid_pass_traffic(c, "sim_");
    std::vector<PassTraffic> passes(grid.begin(), grid.end() - 1);
    // pbf_reorder: order, the gathered x, v and carried state; x, v and p stored.
    passes.push_back(per_particle("sim_reorder", n, 4 + 3 * 16 + 3 * 16));
    passes.push_back(grid.back());
    // dfsph_factors: x_i; each neighbour's x; the factors and the density stored.
    passes.push_back(neighbor_pass("sim_dfsph_factors", c, 1, 16, 0, 16 + 16 + 4));
    const uint32_t rates = shape.divergence_iterations + shape.iterations;
    const uint32_t velocities = rates + 1 + (shape.divergence_iterations > 0 ? 1 : 0);  // the warm starts
    // dfsph_rate: x_i, v_i, the factors, the state loaded and stored, the increment stored; each
    // neighbour's x and v.
    passes.push_back(neighbor_pass("sim_dfsph_rate", c, rates, 32, 0, 6 * 16));
    // dfsph_velocity: x_i, k_i, v loaded and stored; each neighbour's x and k.
    passes.push_back(neighbor_pass("sim_dfsph_velocity", c, velocities, 32, 0, 4 * 16));
    // dfsph_advance: x and v loaded and stored.
    passes.push_back(per_particle("sim_dfsph_advance", n, 4 * 16));
    add_filters(passes, c, shape);
    return passes;
}

}  // namespace

PassTraffic emission_traffic(uint64_t particles, uint64_t emitted, uint64_t held) {
    // flow_emit: each new particle's x and v stored (a lattice offset and its layer read);
    // flow_hold: every particle's x read, the held's x and v stored.
    const uint64_t bytes = emitted * (8 + 80 + 2 * 16) + particles * 16 + held * 2 * 16;
    return {"sim_emit", 1, bytes, bytes};
}

PassTraffic removal_traffic(uint64_t particles, uint64_t kept) {
    // flow_sinks' mark: x read, keep and rank stored; the scan of the ranks; its order: keep and
    // rank read, the kept's order stored; the gather (pbf_reorder) of the kept.
    PassTraffic scan = prefix_sum_traffic(particles, "sim_sinks");
    const uint64_t own = particles * (16 + 4 + 4) + particles * (4 + 4) + kept * 4 + kept * (4 + 2 * 16 + 3 * 16);
    scan.bytes += own;
    scan.unique_bytes += own;
    return scan;
}

std::vector<PassTraffic> step_traffic(const GridCounts& c, const StepShape& shape) {
    if (shape.method == PressureMethod::dfsph) return dfsph_step_traffic(c, shape);
    const uint64_t n = c.particles;
    const std::vector<PassTraffic> grid = grid_pass_traffic(c, "sim_");  // sim_grid_count, ..., sim_neighbor_lists
    std::vector<PassTraffic> passes;
    // pbf_predict: x and v loaded, v and p stored.
    passes.push_back(per_particle("sim_predict", n, 16 + 16 + 16 + 16));
    passes.insert(passes.end(), grid.begin(), grid.end() - 1);
    // pbf_reorder: order, the gathered x and v (a permutation: each once); x, v, p stored.
    passes.push_back(per_particle("sim_reorder", n, 4 + 16 + 16 + 3 * 16));
    passes.push_back(grid.back());
    // pbf_lambda: p_i; each neighbour's p; q = (p, lambda) and density stored.
    passes.push_back(neighbor_pass("sim_lambda", c, shape.iterations, 16, 0, 16 + 16 + 4));
    // pbf_correct: q_i; each neighbour's q; p stored. The last iteration stores v and x instead
    // of p, having loaded x: 32 B a particle more.
    PassTraffic correct = neighbor_pass("sim_correct", c, shape.iterations, 16, 0, 16 + 16);
    correct.bytes += 32 * n;
    correct.unique_bytes += 32 * n;
    passes.push_back(correct);
    add_filters(passes, c, shape);
    return passes;
}

uint64_t total_bytes(const std::vector<PassTraffic>& passes) {
    uint64_t sum = 0;
    for (const PassTraffic& p : passes) sum += p.bytes;
    return sum;
}

uint64_t total_unique_bytes(const std::vector<PassTraffic>& passes) {
    uint64_t sum = 0;
    for (const PassTraffic& p : passes) sum += p.unique_bytes;
    return sum;
}

}  // namespace aquaform
