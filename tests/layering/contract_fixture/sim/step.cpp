#include "shaders/shared/core/compat.h"
#include "shaders/shared/sim/sim_layout.h"
