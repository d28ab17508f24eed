// The mesh obstacles as the renderers draw them: the solver's maps (sim/boundary.h), traced in
// common/environment.glsl, so that what is drawn is what the fluid meets. Static boxes come with
// the ParticleDomain and are drawn as boxes.
#pragma once

#include <vector>

#include "gpu/buffer.h"
#include "shaders/shared/solids/tank_layout.h"

namespace aquaform {

/// The obstacles' map nodes on the GPU and each one's frame and grid at the frame drawn.
struct SolidsView {
    const gpu::Buffer* nodes = nullptr;
    std::vector<shader::SolidParams> table;
};

/// Adds the obstacles of `solids` (nullptr: none) to a frame's tank parameters.
inline void add_solids(shader::TankParams& tank, const SolidsView* solids) {
    if (!solids || !solids->nodes) return;
    const size_t n = std::min<size_t>(solids->table.size(), TANK_MAX_BOXES);
    for (size_t i = 0; i < n; ++i) tank.solids[i] = solids->table[i];
    tank.counts.z = uint32_t(n);
}

/// The buffer bound as solid_nodes: the obstacles' nodes, or `stand_in` when there are none (a
/// bound buffer the shader then never reads).
inline const gpu::Buffer& solid_nodes(const SolidsView* solids, const gpu::Buffer& stand_in) {
    return solids && solids->nodes ? *solids->nodes : stand_in;
}

}  // namespace aquaform
