// Layout of the exclusive prefix sum over uint arrays (grid/prefix_sum.h): each level scans blocks
// of SCAN_BLOCK elements in place and writes the block totals for the next level to scan.
#ifndef AQUAFORM_SCAN_LAYOUT_H
#define AQUAFORM_SCAN_LAYOUT_H
#include "../core/compat.h"

#define SCAN_WORKGROUP 256
#define SCAN_PER_THREAD 4
#define SCAN_BLOCK (SCAN_WORKGROUP * SCAN_PER_THREAD)

AF_BEGIN

struct ScanPush {
    uint count;  ///< elements to scan at this level
    uint pad0;
    uint pad1;
    uint pad2;
};

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::ScanPush) == 16);
#endif

#endif
