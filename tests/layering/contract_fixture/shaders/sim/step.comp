#version 460
#include "shared/sim/sim_layout.h"
#include "common/helper.glsl"
