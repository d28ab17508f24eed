#include "sim/pbf_reference.h"

#include <cmath>

#include "shaders/shared/grid_layout.h"

namespace aquaform {

namespace {

using shader::SimParams;

/// Buckets by cell, built once per step like the GPU grid.
class CpuGrid {
public:
    CpuGrid(const SimParams& p, const std::vector<glm::vec4>& positions)
        : origin_cell_(p.grid_origin_cell), dims_(p.grid_dims), cells_(p.grid_dims.w) {
        for (uint32_t i = 0; i < positions.size(); ++i)
            cells_[shader::grid_linear(cell(glm::vec3(positions[i])), dims_)].push_back(i);
    }

    glm::ivec3 cell(glm::vec3 x) const { return shader::grid_cell(x, origin_cell_, dims_); }

    template <typename Visit>
    void for_each_candidate(glm::vec3 x, Visit visit) const {
        const glm::ivec3 c = cell(x);
        for (int k = 0; k < 27; ++k) {
            glm::ivec3 n = c + glm::ivec3(k % 3, (k / 3) % 3, k / 9) - glm::ivec3(1);
            if (glm::any(glm::lessThan(n, glm::ivec3(0))) ||
                glm::any(glm::greaterThanEqual(n, glm::ivec3(dims_))))
                continue;
            for (uint32_t j : cells_[shader::grid_linear(n, dims_)]) visit(j);
        }
    }

private:
    glm::vec4 origin_cell_;
    glm::uvec4 dims_;
    std::vector<std::vector<uint32_t>> cells_;
};

glm::vec3 xyz(const glm::vec4& v) { return glm::vec3(v); }

void compute_lambda(const SimParams& p, const CpuGrid& grid, const std::vector<glm::vec4>& pos,
                    std::vector<float>& lambda, std::vector<float>& density) {
    for (uint32_t i = 0; i < pos.size(); ++i) {
        const glm::vec3 pi = xyz(pos[i]);
        float rho = 0.0f, sum_grad2 = 0.0f;
        glm::vec3 grad_i(0.0f);
        grid.for_each_candidate(pi, [&](uint32_t j) {
            glm::vec3 r = pi - xyz(pos[j]);
            float r2 = glm::dot(r, r);
            if (r2 >= p.h2) return;
            rho += shader::poly6(r2, p.h2, p.poly6_coeff);
            glm::vec3 g = p.volume * shader::spiky_gradient(r, std::sqrt(r2), p.h, p.spiky_coeff);
            grad_i += g;
            sum_grad2 += glm::dot(g, g);
        });
        rho *= p.mass;
        float constraint = std::max(rho / p.rest_density - 1.0f, 0.0f);
        lambda[i] = -constraint / (sum_grad2 + glm::dot(grad_i, grad_i) + p.epsilon);
        density[i] = rho;
    }
}

}  // namespace

void reference_step(const SimParams& p, const ReferenceSettings& settings, CpuParticles& s) {
    const size_t n = s.x.size();
    std::vector<glm::vec4> pred(n);
    for (size_t i = 0; i < n; ++i) {
        glm::vec3 v = shader::pbf_cap_speed(xyz(s.v[i]) + p.dt * xyz(p.gravity), p);
        s.v[i] = glm::vec4(v, s.v[i].w);
        pred[i] = glm::vec4(shader::pbf_collide(xyz(s.x[i]) + p.dt * v, p), 0.0f);
    }
    const CpuGrid grid(p, pred);
    std::vector<float> lambda(n);
    s.density.assign(n, 0.0f);
    std::vector<glm::vec4> next(n);
    for (uint32_t it = 0; it < settings.iterations; ++it) {
        compute_lambda(p, grid, pred, lambda, s.density);
        for (uint32_t i = 0; i < n; ++i) {
            const glm::vec3 pi = xyz(pred[i]);
            glm::vec3 dp(0.0f);
            grid.for_each_candidate(pi, [&](uint32_t j) {
                glm::vec3 r = pi - xyz(pred[j]);
                float r2 = glm::dot(r, r);
                if (r2 >= p.h2 || j == i) return;
                float s_corr = shader::pbf_scorr(shader::poly6(r2, p.h2, p.poly6_coeff), p);
                dp += (lambda[i] + lambda[j] + s_corr) * shader::spiky_gradient(r, std::sqrt(r2), p.h, p.spiky_coeff);
            });
            next[i] = glm::vec4(shader::pbf_collide(pi + p.volume * dp, p), 0.0f);
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
    for (uint32_t i = 0; i < n; ++i) {
        const glm::vec3 xi = xyz(s.x[i]);
        const glm::vec3 vi = xyz(s.v[i]);
        glm::vec3 dv(0.0f), w(0.0f);
        grid.for_each_candidate(xi, [&](uint32_t j) {
            glm::vec3 r = xi - xyz(s.x[j]);
            float r2 = glm::dot(r, r);
            if (r2 >= p.h2 || j == i) return;
            float vol_j = p.mass / std::max(s.density[j], 1.0e-6f * p.rest_density);
            glm::vec3 vij = xyz(s.v[j]) - vi;
            dv += vol_j * vij * shader::poly6(r2, p.h2, p.poly6_coeff);
            w += vol_j * glm::cross(vij, -shader::spiky_gradient(r, std::sqrt(r2), p.h, p.spiky_coeff));
        });
        v_new[i] = glm::vec4(vi + p.viscosity * dv, s.v[i].w);
        omega[i] = glm::vec4(w, glm::length(w));
    }
    s.v = v_new;
    if (!settings.vorticity) return;
    for (uint32_t i = 0; i < n; ++i) {
        const glm::vec3 xi = xyz(s.x[i]);
        glm::vec3 eta(0.0f);
        grid.for_each_candidate(xi, [&](uint32_t j) {
            glm::vec3 r = xi - xyz(s.x[j]);
            float r2 = glm::dot(r, r);
            if (r2 >= p.h2 || j == i) return;
            float vol_j = p.mass / std::max(s.density[j], 1.0e-6f * p.rest_density);
            eta += vol_j * (omega[j].w - omega[i].w) * shader::spiky_gradient(r, std::sqrt(r2), p.h, p.spiky_coeff);
        });
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
