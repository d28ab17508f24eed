// Water that comes and goes (sim/fluid_flow.h): the layers the nozzles emit and hold, and the
// sinks that remove particles, as the GPU passes read them (shaders/sim/flow_*.comp).
//
// A nozzle emits its water in layers of a lattice (sim/flow_spec.h NozzleLattice). The host
// schedules them (sim/flow_schedule.h): each step it uploads the layers that leave the nozzles
// in that step (flow_emit.comp writes them into the free slots after the alive particles) and
// the layers still within a kernel radius of their nozzle, which flow_hold.comp puts back on
// their lattice at the nozzle's speed after the pressure solve: the water a nozzle makes is a
// lattice at rest density moving at its speed until it has a full neighbourhood behind it, so
// that nothing pushes it back into the nozzle or bursts out of it.
#ifndef AQUAFORM_FLOW_LAYOUT_H
#define AQUAFORM_FLOW_LAYOUT_H
#include "../core/compat.h"

/// Layers in a step's table: emitted and held together (8 emitters, a few layers each).
#define FLOW_MAX_LAYERS 96
#define FLOW_MAX_SINKS 8
#define FLOW_SINK_BOX 0u
#define FLOW_SINK_PLANE 1u

AF_BEGIN

/// One lattice layer of a nozzle at the end of the step being recorded.
struct FlowLayer {
    vec4 origin;    ///< xyz: the layer's centre [m]
    vec4 velocity;  ///< xyz: the nozzle's velocity [m/s]; w: its particles' tag
    vec4 across;    ///< xyz: the lattice's first axis (FlowLattice offsets' x)
    vec4 up;        ///< xyz: its second axis (offsets' y)
    uvec4 ids;      ///< x: id of its first particle; y: its first lattice offset; z: its particles; w: its first slot
};

#define FLOW_MARK 0u
#define FLOW_ORDER 1u

/// Push constants of the flow passes.
struct FlowPush {
    uint count;        ///< emit: the particles emitted; hold, sinks: the alive particles
    uint first_layer;  ///< emit, hold: the layers of the table it reads
    uint layers;
    uint min_id;      ///< hold: no held particle has a smaller id
    uint zero_carry;  ///< emit: 1 zeroes the new particles' carried state (DFSPH's warm start)
    uint phase;       ///< sinks: FLOW_MARK or FLOW_ORDER
    uint pad0;
    uint pad1;
};

/// A sink: a box (a = min, b = max) or a plane (a = a point on it, b = its normal, into the
/// removed side); a.w: FLOW_SINK_BOX or FLOW_SINK_PLANE (as float).
struct FlowSink {
    vec4 a;
    vec4 b;
};

struct FlowSinks {
    uvec4 count;  ///< x: sinks in use
    FlowSink sinks[FLOW_MAX_SINKS];
};

AF_FN bool flow_in_sink(FlowSink s, vec3 p) {
    if (uint(s.a.w) == FLOW_SINK_BOX)
        return p.x >= s.a.x && p.y >= s.a.y && p.z >= s.a.z && p.x <= s.b.x && p.y <= s.b.y && p.z <= s.b.z;
    return dot(p - vec3(s.a.x, s.a.y, s.a.z), vec3(s.b.x, s.b.y, s.b.z)) > 0.0f;
}

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::FlowLayer) == 80);
static_assert(sizeof(aquaform::shader::FlowSinks) == 16 + 32 * FLOW_MAX_SINKS);
#endif

#endif
