// The whitewater pool as the solver fills it (shared/sim/whitewater_layout.h, sim/whitewater.h)
// and the renderers read it (shared/render/whitewater_draw_layout.h, render/whitewater_layer.h):
// two generations of whitewater particles, x (xyz [m], w: life left [s]) and v (xyz [m/s], w: the
// kind below), and the counters that say which generation is live and how many it holds.
#ifndef AQUAFORM_WHITEWATER_POOL_H
#define AQUAFORM_WHITEWATER_POOL_H

#define WHITEWATER_SPRAY 0u
#define WHITEWATER_FOAM 1u
#define WHITEWATER_BUBBLE 2u

/// The pool's counters (a host-visible uint[16]).
#define WW_LIVE 0u        ///< whitewater particles alive at the step's start (the advect pass reads it)
#define WW_NEXT 1u        ///< claimed slots of the next pool: may pass the capacity (then WW_DROPPED counts the rest)
#define WW_DROPPED 2u     ///< particles that did not fit the pool, summed since the counters were cleared
#define WW_EMITTED 3u     ///< particles made, summed since the counters were cleared
#define WW_KINDS 4u       ///< 4, 5, 6: spray, foam, bubbles alive after the last step
#define WW_GENERATION 7u  ///< which of the pool's two generations the last step filled (the renderers read it)
#define WW_COUNTERS 16u

#endif
