#include "bench/surface_checks.h"

#include <random>

#include "render/surface_settings.h"

namespace aquaform::study {

uint32_t DropletCensus::found() const {
    uint32_t n = 0;
    for (uint32_t p : pixels) n += p > 0;
    return n;
}

DropletCensus droplet_census(const SurfaceFrame& frame, const std::vector<glm::vec3>& centres, float reach) {
    DropletCensus census{std::vector<uint32_t>(centres.size(), 0)};
    for (size_t i = 0; i < frame.hit.size(); ++i) {
        if (!frame.has_surface(i)) continue;
        const glm::vec3 p(frame.hit[i]);
        float best = reach * reach;
        size_t owner = centres.size();
        for (size_t d = 0; d < centres.size(); ++d) {
            const glm::vec3 e = p - centres[d];
            if (const float d2 = glm::dot(e, e); d2 <= best) best = d2, owner = d;
        }
        if (owner < centres.size()) ++census.pixels[owner];
    }
    return census;
}

Sheet one_particle_thick_sheet(glm::vec3 corner, float spacing, int n, float pitch, float jitter, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    Sheet sheet;
    sheet.corner = corner;
    sheet.side = float(n - 1) * pitch * spacing;
    sheet.spacing = spacing;
    for (int x = 0; x < n; ++x)
        for (int y = 0; y < n; ++y) {
            const float jx = unit(rng), jy = unit(rng), jz = unit(rng);  // drawn in order: the same sheet everywhere
            sheet.particles.emplace_back(corner.x + (pitch * x + jitter * jx) * spacing,
                                         corner.y + (pitch * y + jitter * jy) * spacing,
                                         corner.z + 0.15f * jitter * jz * spacing, 0.0f);
        }
    return sheet;
}

SheetCoverage sheet_coverage(const SurfaceFrame& frame, const ViewCamera& camera, const Sheet& sheet, float inset) {
    const CameraBlock view = camera_block(camera, frame.width, frame.height);
    const glm::vec2 lo = glm::vec2(sheet.corner) + inset, hi = glm::vec2(sheet.corner) + sheet.side - inset;
    // Per pixel: 0 outside the square, 1 covered, 2 a gap (not yet given to a hole).
    std::vector<uint8_t> state(frame.hit.size(), 0);
    SheetCoverage c;
    for (uint32_t y = 0; y < frame.height; ++y)
        for (uint32_t x = 0; x < frame.width; ++x) {
            // The pixel's ray where it crosses the sheet's plane.
            const float u = 2.0f * (x + 0.5f) / frame.width - 1.0f, v = 2.0f * (y + 0.5f) / frame.height - 1.0f;
            const glm::vec3 dir = glm::vec3(view.forward) + u * view.forward.w * glm::vec3(view.right) -
                                  v * view.right.w * glm::vec3(view.up);
            if (dir.z == 0.0f) continue;
            const float t = (sheet.corner.z - view.eye.z) / dir.z;
            const glm::vec2 at = glm::vec2(glm::vec3(view.eye) + t * dir);
            if (t <= 0.0f || at.x < lo.x || at.y < lo.y || at.x > hi.x || at.y > hi.y) continue;
            const size_t i = size_t(y) * frame.width + x;
            ++c.inside;
            c.covered += frame.has_surface(i);
            state[i] = frame.has_surface(i) ? 1 : 2;
        }
    // Holes: flood each group of gaps once.
    std::vector<size_t> stack;
    for (size_t seed = 0; seed < state.size(); ++seed) {
        if (state[seed] != 2) continue;
        ++c.holes;
        stack.assign(1, seed);
        state[seed] = 0;
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            const uint32_t x = uint32_t(i % frame.width), y = uint32_t(i / frame.width);
            const size_t next[4] = {x > 0 ? i - 1 : i, x + 1 < frame.width ? i + 1 : i, y > 0 ? i - frame.width : i,
                                    y + 1 < frame.height ? i + frame.width : i};
            for (size_t j : next)
                if (state[j] == 2) state[j] = 0, stack.push_back(j);
        }
    }
    return c;
}

}  // namespace aquaform::study
