#include "sim/pbf_reference.h"

#include <cmath>

#include "shaders/shared/grid/grid_layout.h"

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

}  // namespace

void reference_step(const SimParams& p, const ReferenceSettings& settings, CpuParticles& s,
                    const std::vector<glm::vec4>& boundary_nodes) {
    const size_t n = s.x.size();
    const glm::vec4* nodes = boundary_nodes.data();
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
    if (!settings.xsph && !settings.vorticity) return;

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
