// A helper of no layer: fine for sim's shaders, planted for render's.
#include "shared/sim/sim_layout.h"
