#include "sim/pbf_reference.h"

#include <cmath>

#include "shaders/shared/grid/grid_layout.h"
#include "shaders/shared/sim/dfsph_physics.h"

namespace aquaform {

namespace {

using shader::SimParams;

glm::vec3 xyz(const glm::vec4& v) { return glm::vec3(v); }

/// Neighbours of every particle within h at the predicted positions, found once per step
/// like the GPU's neighbour lists (PBF Algorithm 1, before the solver loop). Candidates come
/// from a bucket grid with the GPU's cell rule; the GPU visits them in a different order,
/// which changes float sums only by rounding.
std::vector<std::vector<uint32_t>> find_neighbors(const SimParams& p, const std::vector<glm::vec4>& pos) {
    std::vector<std::vector<uint32_t>> cells(p.grid_dims.w);
    auto cell_of = [&](const glm::vec4& x) { return shader::grid_cell(xyz(x), p.grid_origin_cell, p.grid_dims); };
    for (uint32_t i = 0; i < pos.size(); ++i) cells[shader::grid_linear(cell_of(pos[i]), p.grid_dims)].push_back(i);
    std::vector<std::vector<uint32_t>> out(pos.size());
    for (uint32_t i = 0; i < pos.size(); ++i) {
        const glm::ivec3 c = cell_of(pos[i]);
        for (int k = 0; k < 27; ++k) {
            glm::ivec3 n = c + glm::ivec3(k % 3, (k / 3) % 3, k / 9) - glm::ivec3(1);
            if (glm::any(glm::lessThan(n, glm::ivec3(0))) ||
                glm::any(glm::greaterThanEqual(n, glm::ivec3(p.grid_dims))))
                continue;
            for (uint32_t j : cells[shader::grid_linear(n, p.grid_dims)]) {
                glm::vec3 d = xyz(pos[i]) - xyz(pos[j]);
                if (j != i && glm::dot(d, d) < p.h2) out[i].push_back(j);
            }
        }
    }
    return out;
}

/// XSPH viscosity and vorticity confinement on the step's final x and v (sim/velocity_filters.h),
/// on the step's neighbour lists.
void reference_filters(const SimParams& p, const ReferenceSettings& settings, CpuParticles& s,
                       const std::vector<std::vector<uint32_t>>& neighbors) {
    if (!settings.xsph && !settings.vorticity) return;
    const size_t n = s.x.size();

    std::vector<glm::vec4> v_new(n), omega(n);
    for (uint32_t i = 0; i < n; ++i) {  // eqs. 15, 17
        const glm::vec3 xi = xyz(s.x[i]);
        const glm::vec3 vi = xyz(s.v[i]);
        glm::vec3 dv(0.0f), w(0.0f);
        for (uint32_t j : neighbors[i]) {
            glm::vec3 r = xi - xyz(s.x[j]);
            float r2 = glm::dot(r, r);
            float vol_j = p.mass / std::max(s.density[j], 1.0e-6f * p.rest_density);
            glm::vec3 vij = xyz(s.v[j]) - vi;
            dv += vol_j * vij * shader::poly6(r2, p.h2, p.poly6_coeff);
            w += vol_j * glm::cross(vij, -shader::spiky_gradient(r, r2, p.h, p.spiky_coeff));
        }
        v_new[i] = glm::vec4(vi + p.viscosity * dv, s.v[i].w);
        omega[i] = glm::vec4(w, glm::length(w));
    }
    s.v = v_new;
    if (!settings.vorticity) return;
    for (uint32_t i = 0; i < n; ++i) {  // eq. 16
        const glm::vec3 xi = xyz(s.x[i]);
        glm::vec3 eta(0.0f);
        for (uint32_t j : neighbors[i]) {
            glm::vec3 r = xi - xyz(s.x[j]);
            float r2 = glm::dot(r, r);
            float vol_j = p.mass / std::max(s.density[j], 1.0e-6f * p.rest_density);
            eta += vol_j * (omega[j].w - omega[i].w) * shader::spiky_gradient(r, r2, p.h, p.spiky_coeff);
        }
        float len = glm::length(eta);
        if (len > 1.0e-9f) {
            glm::vec3 a = p.vorticity * glm::cross(eta / len, xyz(omega[i]));
            s.v[i] = glm::vec4(shader::pbf_cap_speed(xyz(s.v[i]) + p.dt * a, p), s.v[i].w);
        }
    }
}

/// DFSPH's velocity pass (dfsph_velocity.comp): v_i -= dt (V sum_j (k_i + k_j) grad W_ij + k_i grad m).
void dfsph_apply(const SimParams& p, const std::vector<std::vector<uint32_t>>& neighbors, const CpuParticles& s,
                 const std::vector<float>& k, const glm::vec4* nodes, std::vector<glm::vec4>& v, bool add_gravity) {
    for (uint32_t i = 0; i < s.x.size(); ++i) {
        const glm::vec3 xi = xyz(s.x[i]);
        glm::vec3 sum(0.0f);
        for (uint32_t j : neighbors[i]) {
            glm::vec3 r = xi - xyz(s.x[j]);
            sum += (k[i] + k[j]) * shader::spiky_gradient(r, glm::dot(r, r), p.h, p.spiky_coeff);
        }
        glm::vec3 vi = xyz(v[i]);
        if (add_gravity) vi = shader::pbf_cap_speed(vi + p.dt * xyz(p.gravity), p);
        vi -= p.dt * (p.volume * sum + k[i] * glm::vec3(shader::pbf_boundary_term(xi, p, nodes)));
        v[i] = glm::vec4(vi, v[i].w);
    }
}

/// One DFSPH solve (DfsphPressure::record_solve): the carried sums `total` applied, then
/// `iterations` of the rate pass (dfsph_rate.comp) and the velocity pass.
void dfsph_solve(const SimParams& p, const std::vector<std::vector<uint32_t>>& neighbors, CpuParticles& s,
                 const std::vector<glm::vec3>& factors, std::vector<float>& total, bool density_solve,
                 uint32_t iterations, const glm::vec4* nodes) {
    const size_t n = s.x.size();
    dfsph_apply(p, neighbors, s, total, nodes, s.v, density_solve);
    std::vector<float> added(n);
    for (uint32_t it = 0; it < iterations; ++it) {
        for (uint32_t i = 0; i < n; ++i) {
            const glm::vec3 xi = xyz(s.x[i]), vi = xyz(s.v[i]);
            float rate = 0.0f;
            for (uint32_t j : neighbors[i]) {
                glm::vec3 r = xi - xyz(s.x[j]);
                rate += glm::dot(vi - xyz(s.v[j]), shader::spiky_gradient(r, glm::dot(r, r), p.h, p.spiky_coeff));
            }
            rate = p.volume * rate + glm::dot(vi, glm::vec3(shader::pbf_boundary_term(xi, p, nodes)));
            const glm::vec3 f = factors[i];
            const float next = density_solve ? shader::dfsph_density_total(total[i], f.x, f.y, rate, p)
                                             : shader::dfsph_divergence_total(total[i], f.x, rate, f.z, p);
            added[i] = next - total[i];
            total[i] = next;
        }
        dfsph_apply(p, neighbors, s, added, nodes, s.v, false);
    }
}

/// A DFSPH step (DfsphPressure::record_step), the sums of k carried in s.carry.
void reference_dfsph_step(const SimParams& p, const ReferenceSettings& settings, CpuParticles& s,
                          const glm::vec4* nodes) {
    const size_t n = s.x.size();
    s.carry.resize(n, glm::vec4(0.0f));
    const auto neighbors = find_neighbors(p, s.x);
    std::vector<glm::vec3> factors(n);  // a_i, rho_i / rho0, the neighbours counted (dfsph_factors.comp)
    s.density.assign(n, 0.0f);
    for (uint32_t i = 0; i < n; ++i) {
        const glm::vec3 xi = xyz(s.x[i]);
        float kernel_sum = shader::poly6(0.0f, p.h2, p.poly6_coeff), sum_grad2 = 0.0f, listed = 0.0f;
        glm::vec3 grad_i(0.0f);
        for (uint32_t j : neighbors[i]) {
            glm::vec3 r = xi - xyz(s.x[j]);
            float r2 = glm::dot(r, r);
            kernel_sum += shader::poly6(r2, p.h2, p.poly6_coeff);
            glm::vec3 g = p.volume * shader::spiky_gradient(r, r2, p.h, p.spiky_coeff);
            grad_i += g;
            sum_grad2 += glm::dot(g, g);
            listed += 1.0f;
        }
        const glm::vec4 solid = shader::pbf_boundary_term(xi, p, nodes);
        const float relative = p.volume * kernel_sum + solid.w;
        factors[i] = glm::vec3(shader::dfsph_factor(grad_i + glm::vec3(solid), sum_grad2, p), relative,
                               shader::dfsph_neighbors(listed, solid.w, p));
        s.density[i] = p.rest_density * relative;
    }
    std::vector<float> divergence(n), density(n);
    for (size_t i = 0; i < n; ++i) divergence[i] = s.carry[i].x, density[i] = s.carry[i].y;
    if (settings.divergence_iterations > 0)
        dfsph_solve(p, neighbors, s, factors, divergence, false, settings.divergence_iterations, nodes);
    dfsph_solve(p, neighbors, s, factors, density, true, settings.iterations, nodes);
    for (size_t i = 0; i < n; ++i) {  // dfsph_advance.comp
        const glm::vec3 xi = xyz(s.x[i]), vi = shader::pbf_cap_speed(xyz(s.v[i]), p);
        const glm::vec3 moved = xi + p.dt * vi, reached = shader::pbf_collide(xi, moved, p, nodes);
        s.v[i] = glm::vec4(reached == moved ? vi : (reached - xi) * p.inv_dt, s.v[i].w);
        s.x[i] = glm::vec4(reached, s.x[i].w);
        s.carry[i] = glm::vec4(divergence[i], density[i], 0.0f, 0.0f);
    }
    reference_filters(p, settings, s, neighbors);
}

}  // namespace

void reference_step(const SimParams& p, const ReferenceSettings& settings, CpuParticles& s,
                    const std::vector<glm::vec4>& boundary_nodes) {
    const glm::vec4* nodes = boundary_nodes.data();
    if (settings.method == PressureMethod::dfsph) return reference_dfsph_step(p, settings, s, nodes);
    const size_t n = s.x.size();
    std::vector<glm::vec4> pred(n);
    for (size_t i = 0; i < n; ++i) {
        glm::vec3 v = shader::pbf_cap_speed(xyz(s.v[i]) + p.dt * xyz(p.gravity), p);
        s.v[i] = glm::vec4(v, s.v[i].w);
        pred[i] = glm::vec4(shader::pbf_predicted_position(xyz(s.x[i]), v, p, nodes), 0.0f);
    }
    const auto neighbors = find_neighbors(p, pred);
    std::vector<float> lambda(n);
    s.density.assign(n, 0.0f);
    std::vector<glm::vec4> next(n);
    for (uint32_t it = 0; it < settings.iterations; ++it) {
        for (uint32_t i = 0; i < n; ++i) {  // eqs. 1, 8, 9, 11
            const glm::vec3 pi = xyz(pred[i]);
            float rho = shader::poly6(0.0f, p.h2, p.poly6_coeff), sum_grad2 = 0.0f;
            glm::vec3 grad_i(0.0f);
            for (uint32_t j : neighbors[i]) {
                glm::vec3 r = pi - xyz(pred[j]);
                float r2 = glm::dot(r, r);
                rho += shader::poly6(r2, p.h2, p.poly6_coeff);
                glm::vec3 g = p.volume * shader::spiky_gradient(r, r2, p.h, p.spiky_coeff);
                grad_i += g;
                sum_grad2 += glm::dot(g, g);
            }
            const glm::vec4 solid = shader::pbf_boundary_term(pi, p, nodes);
            rho = p.mass * rho + p.rest_density * solid.w;
            grad_i += glm::vec3(solid);
            float constraint = std::max(rho / p.rest_density - 1.0f, p.constraint_min);
            lambda[i] = -constraint / (sum_grad2 + glm::dot(grad_i, grad_i) + p.epsilon);
            s.density[i] = rho;
        }
        for (uint32_t i = 0; i < n; ++i) {  // eqs. 13, 14
            const glm::vec3 pi = xyz(pred[i]);
            glm::vec3 dp(0.0f);
            for (uint32_t j : neighbors[i]) {
                glm::vec3 r = pi - xyz(pred[j]);
                float r2 = glm::dot(r, r);
                float s_corr = shader::pbf_scorr(shader::poly6(r2, p.h2, p.poly6_coeff), p);
                dp += (lambda[i] + lambda[j] + s_corr) * shader::spiky_gradient(r, r2, p.h, p.spiky_coeff);
            }
            const glm::vec3 solid_dp = lambda[i] * glm::vec3(shader::pbf_boundary_term(pi, p, nodes));
            next[i] = glm::vec4(shader::pbf_collide(pi, pi + p.volume * dp + solid_dp, p, nodes), 0.0f);
        }
        std::swap(pred, next);
    }
    for (size_t i = 0; i < n; ++i) {
        glm::vec3 v = shader::pbf_cap_speed((xyz(pred[i]) - xyz(s.x[i])) * p.inv_dt, p);
        s.v[i] = glm::vec4(v, s.v[i].w);
        s.x[i] = glm::vec4(xyz(pred[i]), s.x[i].w);
    }
    reference_filters(p, settings, s, neighbors);
}

std::vector<std::vector<uint32_t>> brute_force_neighbors(const std::vector<glm::vec4>& positions, float radius) {
    std::vector<std::vector<uint32_t>> out(positions.size());
    const float r2max = radius * radius;
    for (uint32_t i = 0; i < positions.size(); ++i)
        for (uint32_t j = 0; j < positions.size(); ++j) {
            glm::vec3 d = glm::vec3(positions[i]) - glm::vec3(positions[j]);
            if (j != i && glm::dot(d, d) < r2max) out[i].push_back(j);
        }
    return out;
}

}  // namespace aquaform
