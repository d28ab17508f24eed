// What one frame draws, as one value: the particles and everything drawn with them. Every render
// family takes it whole in record()/render(), so that none can be handed half a frame; the
// session makes it (SimulationSession::frame_input), and a new input is one more field here.
#pragma once

#include <cstdint>
#include <string>

#include "core/error.h"
#include "gpu/buffer.h"

namespace aquaform {

class NeighborGrid;
struct SolidsView;
struct WhitewaterView;

struct FrameInput {
    const gpu::Buffer* positions = nullptr;  ///< vec4 per particle, xyz in metres
    uint32_t count = 0;
    /// The grid `positions` are sorted by, a grid of those very positions (the solver's frame
    /// grid): a family that searches neighbours on cells of the same size reads the particles in
    /// place instead of building its own grid (SurfaceRenderer, DensitySampler). nullptr: none.
    const NeighborGrid* grid = nullptr;
    const SolidsView* solids = nullptr;  ///< the mesh obstacles (render/solids_view.h); nullptr: none
    /// The whitewater drawn over the frame (render/whitewater_layer.h); nullptr: none, and the
    /// frame is the method's own, bit for bit.
    const WhitewaterView* whitewater = nullptr;

    FrameInput() = default;
    /// Particles alone: no grid, no solids, no whitewater (tools and tests of one family).
    FrameInput(const gpu::Buffer& particles, uint32_t particle_count) : positions(&particles), count(particle_count) {}

    /// Throws a Failure naming `who` when there are more particles than it was made for
    /// (`capacity`) or the buffer holds fewer than `count` positions.
    void check(const std::string& who, uint32_t capacity) const {
        if (count > capacity)
            throw Failure(who + ": " + std::to_string(count) + " particles, but it was made for " +
                          std::to_string(capacity));
        if (!positions || positions->size < uint64_t(count) * 16)
            throw Failure(who + ": the positions buffer '" + (positions ? positions->name : std::string("(none)")) +
                          "' holds fewer than " + std::to_string(count) + " vec4 positions");
    }
};

}  // namespace aquaform
