// Morton (Z-order) codes of grid cells: 10 bits per axis, x in the lowest bit of each triple.
#ifndef AQUAFORM_MORTON_H
#define AQUAFORM_MORTON_H
#include "../core/compat.h"

AF_BEGIN

/// Largest cell coordinate a 30-bit code can hold (grids are at most 1024 cells per axis).
const uint MORTON_MAX_CELLS_PER_AXIS = 1024u;

/// Spreads the low 10 bits of v so that bit k moves to bit 3k.
AF_FN uint morton_spread(uint v) {
    v &= 0x3ffu;
    v = (v | (v << 16u)) & 0x030000ffu;
    v = (v | (v << 8u)) & 0x0300f00fu;
    v = (v | (v << 4u)) & 0x030c30c3u;
    v = (v | (v << 2u)) & 0x09249249u;
    return v;
}

/// Inverse of morton_spread.
AF_FN uint morton_compact(uint v) {
    v &= 0x09249249u;
    v = (v | (v >> 2u)) & 0x030c30c3u;
    v = (v | (v >> 4u)) & 0x0300f00fu;
    v = (v | (v >> 8u)) & 0x030000ffu;
    v = (v | (v >> 16u)) & 0x000003ffu;
    return v;
}

AF_FN uint morton_encode(uvec3 c) {
    return morton_spread(c.x) | (morton_spread(c.y) << 1u) | (morton_spread(c.z) << 2u);
}

AF_FN uvec3 morton_decode(uint code) {
    return uvec3(morton_compact(code), morton_compact(code >> 1u), morton_compact(code >> 2u));
}

AF_END

#endif
