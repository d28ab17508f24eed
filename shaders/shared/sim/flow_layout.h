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
#define FLOW_SINK_MESH 2u

// A mesh sink's signed distances (sim/flow_spec.h), one float a node. GLSL: a pass that tests
// sinks declares the buffer and FLOW_SINK_PASS before including this file,
//   layout(std430, binding = N) readonly buffer SinkNodes { float sink_nodes[]; };
// C++: the functions take the node array last.
#ifdef __cplusplus
#define FLOW_SINK_NODES , const float* sink_nodes
#define FLOW_SINK_NODES_ARGS , sink_nodes
#else
#define FLOW_SINK_NODES
#define FLOW_SINK_NODES_ARGS
#endif

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

/// A sink: a box (a = min, b = max), a plane (a = a point on it, b = its normal, into the
/// removed side) or a mesh volume (a = its distance grid's first node, b.x = the node spacing,
/// map = the nodes along each axis and the first one's index in sink_nodes); a.w: FLOW_SINK_BOX,
/// FLOW_SINK_PLANE or FLOW_SINK_MESH (as float).
struct FlowSink {
    vec4 a;
    vec4 b;
    uvec4 map;
};

struct FlowSinks {
    uvec4 count;  ///< x: sinks in use
    FlowSink sinks[FLOW_MAX_SINKS];
};

#if defined(__cplusplus) || defined(FLOW_SINK_PASS)
/// A mesh sink's signed distance at p, trilinear between its nodes (negative inside); outside
/// its grid, which reaches beyond the mesh, the distance is +1 m.
AF_FN float flow_sink_distance(FlowSink s, vec3 p FLOW_SINK_NODES) {
    vec3 g = (p - vec3(s.a.x, s.a.y, s.a.z)) / s.b.x;
    vec3 last = vec3(float(s.map.x) - 1.0f, float(s.map.y) - 1.0f, float(s.map.z) - 1.0f);
    if (g.x < 0.0f || g.y < 0.0f || g.z < 0.0f || g.x > last.x || g.y > last.y || g.z > last.z) return 1.0f;
    vec3 cell = min(floor(g), last - vec3(1.0f));
    vec3 f = g - cell;
    uint sy = s.map.x, sz = s.map.x * s.map.y;
    uint base = s.map.w + uint(cell.x) + uint(cell.y) * sy + uint(cell.z) * sz;
    float d = 0.0f;
    for (uint k = 0u; k < 8u; ++k) {
        vec3 w3 = vec3((k & 1u) != 0u ? f.x : 1.0f - f.x, (k & 2u) != 0u ? f.y : 1.0f - f.y,
                       (k & 4u) != 0u ? f.z : 1.0f - f.z);
        uint node = base + ((k & 1u) != 0u ? 1u : 0u) + ((k & 2u) != 0u ? sy : 0u) + ((k & 4u) != 0u ? sz : 0u);
        d += w3.x * w3.y * w3.z * sink_nodes[node];
    }
    return d;
}

/// Whether sink s takes a particle at p. The host's checks (sim/flow_spec.h) call this too.
AF_FN bool flow_in_sink(FlowSink s, vec3 p FLOW_SINK_NODES) {
    uint kind = uint(s.a.w);
    if (kind == FLOW_SINK_BOX)
        return p.x >= s.a.x && p.y >= s.a.y && p.z >= s.a.z && p.x <= s.b.x && p.y <= s.b.y && p.z <= s.b.z;
    if (kind == FLOW_SINK_PLANE) return dot(p - vec3(s.a.x, s.a.y, s.a.z), vec3(s.b.x, s.b.y, s.b.z)) > 0.0f;
    return flow_sink_distance(s, p FLOW_SINK_NODES_ARGS) < 0.0f;
}
#endif

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::FlowLayer) == 80);
static_assert(sizeof(aquaform::shader::FlowSinks) == 16 + 48 * FLOW_MAX_SINKS);
#endif

#endif
